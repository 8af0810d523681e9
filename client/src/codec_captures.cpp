// The capture log's JSON (codec.hpp): captures' params, its pages and the
// capture topic's notifications (docs/api.md, "Captures").
#include <algorithm>

#include "codec.hpp"

namespace gport::client::codec {

json captures_params(std::uint64_t since, std::optional<std::uint32_t> limit) {
    json params = {{"since", since}};
    if (limit) {
        params["limit"] = *limit;
    }
    return params;
}

CaptureEntry capture_entry(const json& capture) {
    if (!capture.is_object()) {
        throw Error(ErrorCode::kBadReply, "capture: expected a JSON object from gportd");
    }
    const auto report = photo_report(json{{"capture", capture}});
    CaptureEntry entry;
    entry.capture = report.capture.value_or(Capture{});
    entry.attitude = report.attitude;
    if (const auto meta = capture.find("meta"); meta != capture.end() && meta->is_object()) {
        entry.meta = meta->dump();
    }
    if (const auto peer = capture.find("client"); peer != capture.end() && peer->is_object()) {
        entry.client =
            Peer{peer->value("id", std::int64_t{0}), peer->value("pid", std::int64_t{0}),
                 peer->value("uid", std::int64_t{0}), peer->value("gid", std::int64_t{0})};
        const auto name = peer->value("name", json());
        entry.client_name = name.is_string() ? name.get<std::string>() : std::string();
    }
    return entry;
}

namespace {

// A member that is a number, else empty (absent, null, or mistyped: a
// server that lies gets no value, never a crash).
std::optional<double> number(const json& object, const char* name) {
    const auto it = object.find(name);
    return it != object.end() && it->is_number() ? std::optional(it->get<double>()) : std::nullopt;
}

std::optional<std::int64_t> integer(const json& object, const char* name) {
    const auto it = object.find(name);
    return it != object.end() && it->is_number_integer() ? std::optional(it->get<std::int64_t>())
                                                         : std::nullopt;
}

std::optional<int> small(const json& object, const char* name) {
    const auto value = integer(object, name);
    return value && *value >= 0 && *value <= 255 ? std::optional(static_cast<int>(*value))
                                                 : std::nullopt;
}

CaptureVehicle capture_vehicle(const json& v) {
    const auto tagged = v.find("tagged");
    if (!v.is_object() || tagged == v.end() || !tagged->is_boolean()) {
        throw Error(ErrorCode::kBadReply,
                    "capture: \"vehicle\" must be null or an object with \"tagged\" from gportd");
    }
    CaptureVehicle out;
    out.tagged = tagged->get<bool>();
    out.utc_us = integer(v, "utc_us");
    if (const auto why = v.find("why"); why != v.end() && why->is_string()) {
        out.why = why->get<std::string>();
    }
    if (!out.tagged) {
        return out;
    }
    const auto lat = number(v, "lat");
    const auto lon = number(v, "lon");
    const auto alt = number(v, "alt_msl_m");
    if (!lat || !lon || !alt) {
        throw Error(ErrorCode::kBadReply,
                    "capture: a tagged \"vehicle\" needs lat, lon and alt_msl_m from gportd");
    }
    out.lat = *lat;
    out.lon = *lon;
    out.alt_msl_m = *alt;
    out.alt_rel_m = number(v, "alt_rel_m");
    if (const auto vel = v.find("velocity_ned");
        vel != v.end() && vel->is_array() && vel->size() == 3 &&
        std::all_of(vel->begin(), vel->end(), [](const json& x) { return x.is_number(); })) {
        out.velocity_ned = {(*vel)[0].get<double>(), (*vel)[1].get<double>(),
                            (*vel)[2].get<double>()};
    }
    out.heading_deg = number(v, "heading_deg");
    out.h_acc_m = number(v, "h_acc_m");
    out.v_acc_m = number(v, "v_acc_m");
    out.fix = small(v, "fix");
    out.satellites = small(v, "satellites");
    out.age_ms = integer(v, "age_ms").value_or(0);
    return out;
}

}  // namespace

CaptureStamp capture_stamp(const json& object) {
    if (!object.is_object()) {
        throw Error(ErrorCode::kBadReply, "capture: expected a JSON object from gportd");
    }
    // A photo or record result: its capture (none when nothing was sent).
    const auto held = object.find("capture");
    if (held != object.end() && !object.contains("index")) {
        return held->is_object() ? capture_stamp(*held) : CaptureStamp{};
    }
    const json& capture = object;
    CaptureStamp stamp;
    stamp.line_mono_us = integer(capture, "line_mono_us");
    stamp.shutter_mono_us = integer(capture, "shutter_mono_us");
    if (const auto v = capture.find("vehicle"); v != capture.end() && !v->is_null()) {
        stamp.vehicle = capture_vehicle(*v);
    }
    return stamp;
}

// `more` as gportd says; a gportd before byte-bounded pages has none: more
// while pages are not empty. Never more when `next` does not advance, so a
// caller paging on it cannot loop for ever.
CapturesPage captures_page(const json& result, std::uint64_t since) {
    if (!result.is_object() || !result.contains("captures") || !result["captures"].is_array()) {
        throw Error(ErrorCode::kBadReply, "captures result: expected {\"captures\":[...]}");
    }
    CapturesPage page;
    for (const auto& capture : result["captures"]) {
        page.captures.push_back(capture_entry(capture));
    }
    const auto next = result.value("next", json());
    page.next = next.is_number_unsigned() ? next.get<std::uint64_t>() : since;
    const auto more = result.value("more", json());
    page.more =
        (more.is_boolean() ? more.get<bool>() : !page.captures.empty()) && page.next > since;
    return page;
}

std::optional<CaptureEntry> capture_notification(const json& message) {
    if (message.value("method", json()) != "capture") {
        return std::nullopt;
    }
    return capture_entry(message.value("params", json()));
}

}  // namespace gport::client::codec
