#include "gport/protocol/messages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace gport::protocol {
namespace {

// Little-endian writer and reader over a fixed buffer.
template <std::size_t N>
class Writer {
  public:
    void u8(std::uint8_t v) { buf_[pos_++] = v; }
    void i8(std::int8_t v) { u8(static_cast<std::uint8_t>(v)); }
    void i16(std::int16_t v) {
        const auto u = static_cast<std::uint16_t>(v);
        u8(static_cast<std::uint8_t>(u & 0xFFU));
        u8(static_cast<std::uint8_t>(u >> 8));
    }
    void axes(const Axes& a) {
        i16(a.roll);
        i16(a.pitch);
        i16(a.yaw);
    }
    template <std::size_t M>
    void bytes(const std::array<std::uint8_t, M>& a) {
        for (auto b : a) {
            u8(b);
        }
    }
    Frame frame(Command cmd) const {
        return Frame::make(static_cast<std::uint8_t>(cmd), {buf_.data(), pos_});
    }

  private:
    std::array<std::uint8_t, N> buf_{};
    std::size_t pos_ = 0;
};

class Reader {
  public:
    explicit Reader(std::span<const std::uint8_t> d) : d_(d) {}
    std::uint8_t u8() { return d_[pos_++]; }
    std::int8_t i8() { return static_cast<std::int8_t>(u8()); }
    std::int16_t i16() {
        const auto lo = u8();
        const auto hi = u8();
        return static_cast<std::int16_t>(static_cast<std::uint16_t>(lo | hi << 8));
    }
    Axes axes() {
        Axes a;
        a.roll = i16();
        a.pitch = i16();
        a.yaw = i16();
        return a;
    }

  private:
    std::span<const std::uint8_t> d_;
    std::size_t pos_ = 0;
};

void write_block(Writer<kSettingsSize>& w, const SettingsBlock& s) {
    w.bytes(s.reserved_head);
    w.u8(s.dead_zone);
    w.u8(s.follow_speed);
    w.i8(s.inverted_raw);
    w.u8(s.reserved_tail);
}

SettingsBlock read_block(Reader& r) {
    SettingsBlock s;
    for (auto& b : s.reserved_head) {
        b = r.u8();
    }
    s.dead_zone = r.u8();
    s.follow_speed = r.u8();
    s.inverted_raw = r.i8();
    s.reserved_tail = r.u8();
    return s;
}

Error wrong_length(std::uint8_t cmd, std::size_t got, std::string_view allowed) {
    return Error{
        fmt::format("command 0x{:02X} carries {} data bytes; {} allowed", cmd, got, allowed)};
}

Result<Message> decode_fixed(Command cmd, std::span<const std::uint8_t> d) {
    Reader r(d);
    switch (cmd) {
        case Command::kGetSettings:
            return Message{GetSettings{}};
        case Command::kSetSettingsAck:
            return Message{SetSettingsAck{}};
        case Command::kSettings:
            return Message{SettingsReport{read_block(r)}};
        case Command::kSetSettings:
            return Message{SetSettings{read_block(r)}};
        default:
            break;
    }
    return Error{"internal: not a fixed-size command"};
}

Result<Message> decode_control(std::span<const std::uint8_t> d) {
    Reader r(d);
    const std::int8_t mode = r.i8();
    if (mode < 1 || mode > 4) {
        return Error{fmt::format(
            "command 0x85 control mode {} is not one of 1 speed, 2 angle, 3 centre, 4 lock", mode)};
    }
    Control c;
    c.mode = static_cast<ControlMode>(mode);
    c.angle = r.axes();
    c.speed = r.axes();
    return Message{c};
}

Result<Message> decode_camera(std::span<const std::uint8_t> d) {
    const auto action = static_cast<std::int8_t>(d[0]);
    if (action != 1 && action != 2) {
        return Error{fmt::format(
            "command 0x86 camera action {} is not one of 1 toggle recording, 2 photo", action)};
    }
    return Message{Camera{static_cast<CameraAction>(action)}};
}

Result<Message> decode_attitude(std::span<const std::uint8_t> d) {
    Reader r(d);
    Attitude a;
    a.imu = r.axes();
    a.hall = r.axes();
    if (d.size() >= kAttitudeWithRatesSize) {
        AttitudeRates rates;
        rates.hall = r.axes();
        rates.imu_x = r.i16();
        rates.imu_y = r.i16();
        rates.imu_z = r.i16();
        a.rates = rates;
    }
    return Message{a};
}

// Data length each known command must carry; attitude takes 12 or more.
bool length_ok(Command cmd, std::size_t n, std::string_view& allowed) {
    switch (cmd) {
        case Command::kGetSettings:
        case Command::kSetSettingsAck:
            allowed = "0 are";
            return n == 0;
        case Command::kSettings:
        case Command::kSetSettings:
            allowed = "15 are";
            return n == kSettingsSize;
        case Command::kControl:
            allowed = "13 are";
            return n == kControlSize;
        case Command::kCamera:
            allowed = "1 is";
            return n == kCameraSize;
        case Command::kAttitude:
            allowed = "12 or more (24 with rates) are";
            return n >= kAttitudeSize;
    }
    return false;
}

bool is_known(std::uint8_t cmd) {
    switch (static_cast<Command>(cmd)) {
        case Command::kGetSettings:
        case Command::kSettings:
        case Command::kSetSettings:
        case Command::kSetSettingsAck:
        case Command::kControl:
        case Command::kCamera:
        case Command::kAttitude:
            return true;
    }
    return false;
}

}  // namespace

Result<std::int16_t> to_centi(double degrees, std::string_view field) {
    const double steps = std::round(degrees * 100.0);
    if (!std::isfinite(steps) || steps > kMaxCenti || steps < -kMaxCenti) {
        return Error{
            fmt::format("{} = {} is out of range; allowed -327.67 to 327.67", field, degrees)};
    }
    return static_cast<std::int16_t>(steps);
}

std::int16_t clamped_centi(double degrees) {
    const double steps = std::round(degrees * 100.0);
    if (std::isnan(steps)) {
        return 0;
    }
    return static_cast<std::int16_t>(std::clamp<double>(steps, -kMaxCenti, kMaxCenti));
}

Result<Axes> to_axes(double roll, double pitch, double yaw) {
    auto r = to_centi(roll, "roll");
    if (!r) {
        return r.error();
    }
    auto p = to_centi(pitch, "pitch");
    if (!p) {
        return p.error();
    }
    auto y = to_centi(yaw, "yaw");
    if (!y) {
        return y.error();
    }
    return Axes{*r, *p, *y};
}

Frame encode(const GetSettings&) {
    return Frame::make(static_cast<std::uint8_t>(Command::kGetSettings), {});
}
Frame encode(const SetSettingsAck&) {
    return Frame::make(static_cast<std::uint8_t>(Command::kSetSettingsAck), {});
}

Frame encode(const SettingsReport& m) {
    Writer<kSettingsSize> w;
    write_block(w, m.block);
    return w.frame(Command::kSettings);
}

Frame encode(const SetSettings& m) {
    Writer<kSettingsSize> w;
    write_block(w, m.block);
    return w.frame(Command::kSetSettings);
}

Frame encode(const Control& m) {
    Writer<kControlSize> w;
    w.i8(static_cast<std::int8_t>(m.mode));
    w.axes(m.angle);
    w.axes(m.speed);
    return w.frame(Command::kControl);
}

Frame encode(const Camera& m) {
    Writer<kCameraSize> w;
    w.i8(static_cast<std::int8_t>(m.action));
    return w.frame(Command::kCamera);
}

Frame encode(const Attitude& m) {
    Writer<kAttitudeWithRatesSize> w;
    w.axes(m.imu);
    w.axes(m.hall);
    if (m.rates) {
        w.axes(m.rates->hall);
        w.i16(m.rates->imu_x);
        w.i16(m.rates->imu_y);
        w.i16(m.rates->imu_z);
    }
    return w.frame(Command::kAttitude);
}

Frame encode(const RawFrame& m) {
    return Frame::make(m.command, m.data);
}

Frame encode(const Message& m) {
    return std::visit([](const auto& msg) { return encode(msg); }, m);
}

Result<Message> decode(const FrameView& frame) {
    if (!is_known(frame.command)) {
        return Message{RawFrame{frame.command, {frame.data.begin(), frame.data.end()}}};
    }
    const auto cmd = static_cast<Command>(frame.command);
    std::string_view allowed;
    if (!length_ok(cmd, frame.data.size(), allowed)) {
        return wrong_length(frame.command, frame.data.size(), allowed);
    }
    switch (cmd) {
        case Command::kControl:
            return decode_control(frame.data);
        case Command::kCamera:
            return decode_camera(frame.data);
        case Command::kAttitude:
            return decode_attitude(frame.data);
        default:
            return decode_fixed(cmd, frame.data);
    }
}

}  // namespace gport::protocol
