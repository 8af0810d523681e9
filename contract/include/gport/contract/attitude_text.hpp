// The attitude notification's text (docs/api.md, "Notifications"), written in
// one place for every part that prints it: gportd's notification lines and
// its `attitude` result (ipc), and libgport-client's attitude_notification
// (gportctl watch). Standard C++17 only, like the rest of the contract.
//
//   {"seq":1042,"t":1763770000.123456,
//    "imu":{"roll":0,"pitch":0,"yaw":-39.29},"hall":{"roll":-19.21,...},
//    "rates":{"hall":{"roll":1.25,...},"imu":{"x":0.12,"y":-2.3,"z":0}},
//    "dropped":3}
//
// Numbers are the shortest text that reads back as the same double, a whole
// value without a fraction ("0", "-1": JSON reads it as an integer), in
// fixed notation from 1e-4 to 1e16 and in exponent form outside (fmt's `{}`,
// which gportd printed with before). "t" is printed from integer
// microseconds, so it always has six decimals (except before 1970, a broken
// clock: then as a number); a value that is not finite (never gportd's: a
// hostile peer's, read by the client) is null. "rates" only when the gimbal sent them;
// "dropped" only when the client has lost samples.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

namespace gport::contract {

// One sample's payload, in degrees and degrees per second.
struct AttitudePayload {
    struct Axes {
        double roll = 0;
        double pitch = 0;
        double yaw = 0;
    };
    struct Rates {
        Axes hall{};
        double x = 0;  // the IMU's own axes
        double y = 0;
        double z = 0;
    };

    std::uint64_t seq = 0;
    std::int64_t t_us = 0;  // receive time, microseconds since the epoch
    Axes imu{};
    Axes hall{};
    std::optional<Rates> rates{};
    std::uint64_t dropped = 0;  // samples this client lost so far; printed when > 0
};

namespace attitude_text_detail {

inline void append_number(std::string& out, double value) {
    if (!std::isfinite(value)) {  // never from gportd; from a hostile peer, as nlohmann writes it
        out += "null";
        return;
    }
    char buffer[32];
    const double magnitude = std::fabs(value);
    const auto format = value == 0 || (magnitude >= 1e-4 && magnitude < 1e16)
                            ? std::chars_format::fixed
                            : std::chars_format::scientific;
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value, format).ptr;
    out.append(buffer, static_cast<std::size_t>(end - buffer));
}

template <typename Integer>
void append_integer(std::string& out, Integer value) {
    char buffer[24];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    out.append(buffer, static_cast<std::size_t>(end - buffer));
}

inline void append_axes(std::string& out, const AttitudePayload::Axes& axes) {
    out += "{\"roll\":";
    append_number(out, axes.roll);
    out += ",\"pitch\":";
    append_number(out, axes.pitch);
    out += ",\"yaw\":";
    append_number(out, axes.yaw);
    out += '}';
}

inline void append_time(std::string& out, std::int64_t us) {
    if (us < 0) {  // before 1970: a broken clock, still valid JSON
        append_number(out, static_cast<double>(us) / 1e6);
        return;
    }
    append_integer(out, us / 1'000'000);
    char fraction[7] = {'.', '0', '0', '0', '0', '0', '0'};
    auto rest = us % 1'000'000;
    for (int i = 6; i > 0; --i, rest /= 10) {
        fraction[i] = static_cast<char>('0' + rest % 10);
    }
    out.append(fraction, sizeof fraction);
}

}  // namespace attitude_text_detail

// Appends the payload object's text (no newline).
inline void append_attitude_payload(std::string& out, const AttitudePayload& payload) {
    using namespace attitude_text_detail;
    out += "{\"seq\":";
    append_integer(out, payload.seq);
    out += ",\"t\":";
    append_time(out, payload.t_us);
    out += ",\"imu\":";
    append_axes(out, payload.imu);
    out += ",\"hall\":";
    append_axes(out, payload.hall);
    if (payload.rates) {
        out += ",\"rates\":{\"hall\":";
        append_axes(out, payload.rates->hall);
        out += ",\"imu\":{\"x\":";
        append_number(out, payload.rates->x);
        out += ",\"y\":";
        append_number(out, payload.rates->y);
        out += ",\"z\":";
        append_number(out, payload.rates->z);
        out += "}}";
    }
    if (payload.dropped > 0) {
        out += ",\"dropped\":";
        append_integer(out, payload.dropped);
    }
    out += '}';
}

inline std::string attitude_payload_text(const AttitudePayload& payload) {
    std::string out;
    out.reserve(256);
    append_attitude_payload(out, payload);
    return out;
}

// The whole `attitude` notification as one NDJSON line, ending in '\n'.
inline std::string attitude_notification_line(const AttitudePayload& payload) {
    std::string out;
    out.reserve(300);
    out += R"({"jsonrpc":"2.0","method":"attitude","params":)";
    append_attitude_payload(out, payload);
    out += "}\n";
    return out;
}

}  // namespace gport::contract
