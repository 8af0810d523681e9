#include "gport/sim/trace.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <variant>

#include "overloaded.hpp"

namespace gport::sim {
namespace {

namespace p = gport::protocol;
using Json = nlohmann::ordered_json;  // keeps t_ms first, as documented

using detail::Overloaded;

Json start(double t_ms) {
    Json j;
    j["t_ms"] = std::round(t_ms * 10.0) / 10.0;
    return j;
}

std::string hex_command(std::uint8_t command) {
    return fmt::format("0x{:02X}", command);
}

Json axes(const p::Axes& a) {
    return Json::array({a.roll, a.pitch, a.yaw});
}

std::string hex_bytes(std::span<const std::uint8_t> bytes) {
    std::string out;
    for (auto b : bytes) {
        out += fmt::format("{:02x}", b);
    }
    return out;
}

void add_block(Json& j, const p::SettingsBlock& b) {
    j["dead_zone"] = b.dead_zone;
    j["follow_speed"] = b.follow_speed;
    j["inverted"] = b.inverted_raw;
    j["reserved"] = hex_bytes(b.reserved_head) + fmt::format("{:02x}", b.reserved_tail);
}

// Fields of a valid frame, by message type.
void add_message(Json& j, const p::Message& message) {
    std::visit(Overloaded{
                   [&](const p::Control& m) {
                       j["mode"] = std::string(p::to_string(m.mode));
                       j["speed"] = axes(m.speed);
                       j["angle"] = axes(m.angle);
                   },
                   [&](const p::Camera& m) {
                       j["action"] = m.action == p::CameraAction::kPhoto ? "photo" : "record";
                   },
                   [&](const p::SetSettings& m) { add_block(j, m.block); },
                   [&](const p::SettingsReport& m) { add_block(j, m.block); },
                   [&](const p::RawFrame& m) { j["len"] = m.data.size(); },
                   [&](const auto&) {},
               },
               message);
}

}  // namespace

std::string trace_received(double t_ms, const Received& r) {
    Json j = start(t_ms);
    switch (r.kind) {
        case Received::Kind::kFrame:
            j["cmd"] = hex_command(r.command);
            if (r.message) {
                add_message(j, *r.message);
            }
            break;
        case Received::Kind::kUnexpected:
            j["event"] = "unexpected_frame";
            j["cmd"] = hex_command(r.command);
            break;
        case Received::Kind::kCrcError:
            j["event"] = "bad_frame";
            j["kind"] = "crc";
            break;
        case Received::Kind::kHeaderError:
            j["event"] = "bad_frame";
            j["kind"] = "header";
            break;
        case Received::Kind::kInvalid:
            j["event"] = "bad_frame";
            j["kind"] = "invalid";
            j["cmd"] = hex_command(r.command);
            j["error"] = r.detail;
            break;
        case Received::Kind::kGarbage:
            j["event"] = "garbage";
            j["bytes"] = r.bytes;
            break;
    }
    return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::string trace_event(double t_ms, std::string_view event, std::string_view path,
                        std::string_view error) {
    Json j = start(t_ms);
    j["event"] = event;
    if (!path.empty()) {
        j["path"] = path;
    }
    if (!error.empty()) {
        j["error"] = error;
    }
    return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace gport::sim
