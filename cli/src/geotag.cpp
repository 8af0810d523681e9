#include "geotag.hpp"

#include <fmt/format.h>

#include <array>
#include <utility>

namespace gport::cli {
namespace {

using nlohmann::json;

// --meta: nested no deeper than gportctl call's params.
constexpr int kMaxMetaDepth = 32;

Result<json, std::string> parse_meta(const std::string& text) {
    bool too_deep = false;
    auto meta = json::parse(
        text,
        [&too_deep](int depth, json::parse_event_t, json&) {
            too_deep = too_deep || depth > kMaxMetaDepth;
            return !too_deep;
        },
        false);
    if (too_deep) {
        return gport::unexpected(fmt::format("--meta nests deeper than {} levels", kMaxMetaDepth));
    }
    if (!meta.is_object()) {
        return gport::unexpected(fmt::format(
            "--meta {}: expected a JSON object, such as '{{\"flight\": \"F12\"}}'",
            meta.is_discarded() ? "is not valid JSON" : "is a " + std::string(meta.type_name())));
    }
    return meta;
}

}  // namespace

Result<std::optional<json>, std::string> geotag_meta(const GeotagArgs& args) {
    if (args.lat.has_value() != args.lon.has_value()) {
        return gport::unexpected(std::string(args.lat ? "--lat needs --lon" : "--lon needs --lat"));
    }
    if (args.alt && !args.lat) {
        return gport::unexpected(std::string("--alt needs --lat and --lon"));
    }
    if (!args.lat && !args.meta) {
        return std::optional<json>();
    }
    json meta = json::object();
    if (args.meta) {
        auto parsed = parse_meta(*args.meta);
        if (!parsed) {
            return gport::unexpected(parsed.error());
        }
        meta = std::move(*parsed);
    }
    const std::array<std::pair<const char*, const std::optional<double>*>, 3> position = {
        {{"lat", &args.lat}, {"lon", &args.lon}, {"alt_m", &args.alt}}};
    for (const auto& [key, value] : position) {
        if (!value->has_value()) {
            continue;
        }
        if (meta.contains(key)) {
            return gport::unexpected(
                fmt::format("--meta has \"{}\" and --{} sets it too: give it once", key,
                            std::string_view(key) == "alt_m" ? "alt" : key));
        }
        meta[key] = **value;
    }
    return std::optional<json>(std::move(meta));
}

}  // namespace gport::cli
