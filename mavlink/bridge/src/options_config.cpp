// The `mavlink` section of gport-mavlink's config file (docs/mavlink.md,
// "Options"): every key checked, an unknown one refused by name.
#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "options_internal.hpp"

namespace gport::mavlink::bridge::detail {

namespace {

using Json = nlohmann::json;

constexpr std::array<std::string_view, 12> kKeys = {
    "socket",   "url",       "sysid",  "gcs_sysid",   "compid",    "attitude_rate_hz",
    "lease_ms", "log_level", "invert", "signing_key", "state_dir", "camera"};

constexpr const char* kKeyList =
    "socket, url, sysid, gcs_sysid, compid, attitude_rate_hz, lease_ms, log_level, invert, "
    "signing_key, state_dir, camera";

template <typename T>
void take(const Json& section, const char* key, T& out) {
    if (section.contains(key)) {
        out = section.at(key).get<T>();
    }
}

// A system id (1 to 255) from an integer; `name` is the key for the error.
std::string id_of(const Json& value, const std::string& name, std::uint8_t& out) {
    if (!value.is_number_integer()) {
        return name + " = " + value.dump() + " is not an integer; allowed 1 to 255";
    }
    const auto id = detail::mavlink_id(value.get<long long>());
    if (!id) {
        return name + " = " + value.dump() + " is out of range; allowed 1 to 255";
    }
    out = *id;
    return {};
}

std::string take_sysid(const Json& m, Options& o) {
    if (!m.contains("sysid")) {
        return {};
    }
    const Json& v = m.at("sysid");
    if (v.is_string() && v.get<std::string>() == "auto") {
        o.sysid.reset();
        return {};
    }
    std::uint8_t id = 0;
    if (auto problem = id_of(v, "mavlink.sysid", id); !problem.empty()) {
        return problem + " or \"auto\"";
    }
    o.sysid = id;
    return {};
}

std::string take_gcs(const Json& m, Options& o) {
    if (!m.contains("gcs_sysid")) {
        return {};
    }
    const Json& v = m.at("gcs_sysid");
    const std::string allowed = "; allowed: a system id 1 to 255, or a list of them ([] for none)";
    if (!v.is_array() && !v.is_number_integer()) {
        return "mavlink.gcs_sysid = " + v.dump() + " is not a list of system ids" + allowed;
    }
    std::vector<std::uint8_t> ids;
    for (const Json& item : v.is_array() ? v : Json::array({v})) {
        std::uint8_t id = 0;
        if (!id_of(item, "mavlink.gcs_sysid", id).empty()) {
            return "mavlink.gcs_sysid: " + item.dump() + " is not a system id" + allowed;
        }
        ids.push_back(id);
    }
    o.gcs_sysids = ids;
    return {};
}

std::string take_path(const Json& m, const char* key, std::string& out) {
    if (!m.contains(key)) {
        return {};
    }
    const Json& v = m.at(key);
    if (!v.is_string() || v.get<std::string>().empty()) {
        return std::string("mavlink.") + key + " = " + v.dump() +
               " is not a path; allowed: a "
               "non-empty string";
    }
    out = v.get<std::string>();
    return {};
}

std::string apply_section(const Json& m, Options& o) {
    for (const auto& [key, value] : m.items()) {
        if (std::find(kKeys.begin(), kKeys.end(), key) == kKeys.end()) {
            return "mavlink." + key + " is unknown; allowed " + kKeyList;
        }
    }
    take(m, "socket", o.socket);
    if (m.contains("url")) {
        std::string error;
        auto endpoint = parse_endpoint(m.at("url").get<std::string>(), error);
        if (!endpoint) {
            return "mavlink.url: " + error;
        }
        o.mavlink = *endpoint;
    }
    for (const auto& problem :
         {take_sysid(m, o), take_gcs(m, o), take_path(m, "signing_key", o.signing_key),
          take_path(m, "state_dir", o.state_dir)}) {
        if (!problem.empty()) {
            return problem;
        }
    }
    if (m.contains("compid")) {
        if (auto problem = id_of(m.at("compid"), "mavlink.compid", o.compid); !problem.empty()) {
            return problem;
        }
    }
    take(m, "attitude_rate_hz", o.attitude_rate_hz);
    take(m, "lease_ms", o.lease_ms);
    take(m, "log_level", o.log_level);
    take(m, "camera", o.camera);
    if (m.contains("invert")) {
        const Json& inv = m.at("invert");
        take(inv, "roll", o.invert.roll);
        take(inv, "pitch", o.invert.pitch);
        take(inv, "yaw", o.invert.yaw);
    }
    return {};
}

}  // namespace

std::string check(const Options& o) {
    if (!(o.attitude_rate_hz >= 0.1 && o.attitude_rate_hz <= 100)) {
        return "attitude rate = " + std::to_string(o.attitude_rate_hz) +
               " Hz is out of range; allowed 0.1 to 100";
    }
    if (o.lease_ms < 50 || o.lease_ms > 60000) {
        return "lease = " + std::to_string(o.lease_ms) + " ms is out of range; allowed 50 to 60000";
    }
    if (std::find(kLogLevels.begin(), kLogLevels.end(), o.log_level) == kLogLevels.end()) {
        return "log level \"" + o.log_level +
               "\" is unknown; allowed trace, debug, info, warn, error, critical, off";
    }
    if (o.socket.empty()) {
        return "the socket path is empty";
    }
    if (o.camera && o.compid == kCameraCompid) {
        return "component id " + std::to_string(o.compid) +
               " is the camera component's (MAV_COMP_ID_CAMERA); give the gimbal another "
               "(default 154) or turn the camera off (--no-camera, camera: false)";
    }
    return {};
}

std::string apply_config(const std::string& path, Options& o) {
    std::ifstream in(path);
    if (!in) {
        return path + ": cannot be read";
    }
    try {
        const Json root = Json::parse(in, nullptr, true, /*ignore_comments=*/true);
        if (!root.is_object() || !root.contains("mavlink") || !root.at("mavlink").is_object()) {
            return path + ": no \"mavlink\" section (an object) at the top level";
        }
        if (auto problem = apply_section(root.at("mavlink"), o); !problem.empty()) {
            return path + ": " + problem;
        }
    } catch (const Json::exception& e) {
        return path + ": " + e.what();
    }
    const std::string problem = check(o);
    return problem.empty() ? problem : path + ": " + problem;
}

}  // namespace gport::mavlink::bridge::detail
