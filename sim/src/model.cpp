#include "gport/sim/model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <variant>

#include "overloaded.hpp"

namespace gport::sim {
namespace {

namespace p = gport::protocol;

using detail::Overloaded;

std::array<double, 3> to_array(const Vec3& v) {
    return {v.roll, v.pitch, v.yaw};
}
Vec3 to_vec(const std::array<double, 3>& a) {
    return {a[0], a[1], a[2]};
}

double seconds(Duration d) {
    return std::chrono::duration<double>(d).count();
}

// Degrees to the wire's 0.01 steps; the model keeps values in range, the
// clamp only guards against a misconfigured base attitude.
p::Axes to_axes(const Vec3& v) {
    return {p::clamped_centi(v.roll), p::clamped_centi(v.pitch), p::clamped_centi(v.yaw)};
}

double wrap180(double degrees) {
    double w = std::fmod(degrees + 180.0, 360.0);
    if (w < 0) {
        w += 360.0;
    }
    return w - 180.0;
}

Received make_received(Received::Kind kind, std::uint8_t command = 0) {
    Received r;
    r.kind = kind;
    r.command = command;
    return r;
}

bool is_slewing(p::ControlMode mode) {
    return mode == p::ControlMode::kAngle || mode == p::ControlMode::kCenter;
}

}  // namespace

protocol::SettingsBlock default_settings() {
    p::SettingsBlock s;
    s.reserved_head = {'G', 'P', 'O', 'R', 'T', 'S', 'I', 'M', 0x01, 0x02, 0x03};
    s.dead_zone = 5;
    s.follow_speed = 10;
    s.inverted_raw = 1;
    s.reserved_tail = 0xA5;
    return s;
}

std::optional<std::string> validate(const ModelOptions& o) {
    if (!std::isfinite(o.stream_rate_hz) || o.stream_rate_hz < 0 ||
        o.stream_rate_hz > kMaxStreamRateHz) {
        return "stream rate must be from 0 (off) to 10000 frames per second";
    }
    if (!std::isfinite(o.slew_deg_s) || o.slew_deg_s <= 0 || o.slew_deg_s > p::kMaxDegrees) {
        return "slew rate must be above 0 and at most 327.67 degrees per second";
    }
    if (o.speed_timeout <= Duration::zero()) {
        return "speed timeout must be positive";
    }
    for (double l : to_array(o.limits)) {
        if (!std::isfinite(l) || l <= 0 || l > 180.0) {
            return "axis limits must be above 0 and at most 180 degrees";
        }
    }
    return std::nullopt;
}

GimbalModel::GimbalModel(ModelOptions options)
    : options_(std::move(options)), settings_(options_.settings) {
    if (auto error = validate(options_)) {
        throw std::invalid_argument(*error);
    }
    next_emit_ = options_.stream_rate_hz > 0 ? emission_time(emit_index_) : Duration::max();
}

Duration GimbalModel::emission_time(std::uint64_t index) const {
    // Computed from the index, not accumulated, so the stream never drifts.
    return Duration(std::llround(static_cast<double>(index) * 1e9 / options_.stream_rate_hz));
}

GimbalModel::Frames GimbalModel::advance(Duration dt) {
    return step(now_ + std::max(dt, Duration::zero()));
}

GimbalModel::Frames GimbalModel::step(Duration now) {
    Frames out;
    while (next_emit_ <= now) {
        integrate(next_emit_);
        out.push_back(p::encode(attitude()));
        ++stats_.attitude_frames;
        next_emit_ = emission_time(++emit_index_);
    }
    integrate(now);
    return out;
}

// Motion is piecewise linear, so integrating an interval in one go is exact:
// speed mode moves until its deadline (then stands), slewing stops on target.
void GimbalModel::integrate(Duration to) {
    if (to <= now_) {
        return;
    }
    const auto limits = to_array(options_.limits);
    if (mode_ == p::ControlMode::kSpeed && speed_until_ > now_) {
        const double dt = seconds(std::min(to, speed_until_) - now_);
        for (std::size_t i = 0; i < 3; ++i) {
            position_[i] = std::clamp(position_[i] + velocity_[i] * dt, -limits[i], limits[i]);
        }
    } else if (is_slewing(mode_)) {
        const double max_step = options_.slew_deg_s * seconds(to - now_);
        for (std::size_t i = 0; i < 3; ++i) {
            const double delta = target_[i] - position_[i];
            position_[i] = std::abs(delta) <= max_step
                               ? target_[i]
                               : position_[i] + std::copysign(max_step, delta);
        }
    }
    now_ = to;
}

ModelState GimbalModel::state() const {
    ModelState s;
    s.mode = mode_;
    s.hall = to_vec(position_);
    const auto limits = to_array(options_.limits);
    std::array<double, 3> rate{};
    for (std::size_t i = 0; i < 3; ++i) {
        if (mode_ == p::ControlMode::kSpeed && speed_until_ > now_) {
            const bool at_stop = (velocity_[i] > 0 && position_[i] >= limits[i]) ||
                                 (velocity_[i] < 0 && position_[i] <= -limits[i]);
            rate[i] = at_stop ? 0.0 : velocity_[i];
        } else if (is_slewing(mode_) && position_[i] != target_[i]) {
            rate[i] = std::copysign(options_.slew_deg_s, target_[i] - position_[i]);
        }
    }
    s.hall_rate = to_vec(rate);
    s.imu = {wrap180(position_[0] + options_.base.roll),
             wrap180(position_[1] + options_.base.pitch),
             wrap180(position_[2] + options_.base.yaw)};
    s.speed_active = mode_ == p::ControlMode::kSpeed && speed_until_ > now_;
    s.recording = recording_;
    s.photos = photos_;
    s.settings = settings_;
    return s;
}

protocol::Attitude GimbalModel::attitude() const {
    const ModelState s = state();
    p::Attitude a;
    a.imu = to_axes(s.imu);
    a.hall = to_axes(s.hall);
    if (options_.form == AttitudeForm::kLong24) {
        // The base stands still, so the camera turns exactly as its joints do.
        const p::Axes rates = to_axes(s.hall_rate);
        a.rates = p::AttitudeRates{rates, rates.roll, rates.pitch, rates.yaw};
    }
    return a;
}

GimbalModel::Frames GimbalModel::receive(std::span<const std::uint8_t> bytes) {
    Frames out;
    stats_.bytes_received += bytes.size();
    p::DecoderStats before = decoder_.stats();
    decoder_.feed(bytes, [&](const p::FrameView& frame) {
        report_decoder_delta(before);
        before = decoder_.stats();
        ++stats_.frames_received;
        handle(frame, out);
    });
    report_decoder_delta(before);
    return out;
}

void GimbalModel::report_decoder_delta(const protocol::DecoderStats& before) {
    const p::DecoderStats& now = decoder_.stats();
    for (auto n = now.header_errors - before.header_errors; n > 0; --n) {
        ++stats_.header_errors;
        notify(make_received(Received::Kind::kHeaderError));
    }
    for (auto n = now.crc_errors - before.crc_errors; n > 0; --n) {
        ++stats_.crc_errors;
        notify(make_received(Received::Kind::kCrcError));
    }
    if (const auto garbage = now.garbage_bytes - before.garbage_bytes; garbage > 0) {
        stats_.garbage_bytes += garbage;
        Received r = make_received(Received::Kind::kGarbage);
        r.bytes = garbage;
        notify(std::move(r));
    }
}

void GimbalModel::notify(Received r) {
    if (listener_) {
        listener_(r);
    }
}

void GimbalModel::handle(const protocol::FrameView& frame, Frames& out) {
    auto decoded = p::decode(frame);
    if (!decoded) {
        ++stats_.invalid_frames;
        Received r = make_received(Received::Kind::kInvalid, frame.command);
        r.detail = decoded.error().message;
        notify(std::move(r));
        return;
    }
    bool expected = true;
    std::visit(Overloaded{
                   [&](const p::GetSettings&) {
                       out.push_back(p::encode(p::SettingsReport{settings_}));
                       ++stats_.replies;
                   },
                   [&](const p::SetSettings& m) {
                       settings_ = m.block;  // whole block: what the client sent is kept
                       out.push_back(p::encode(p::SetSettingsAck{}));
                       ++stats_.replies;
                   },
                   [&](const p::Control& m) { apply(m); },
                   [&](const p::Camera& m) {
                       if (m.action == p::CameraAction::kPhoto) {
                           ++photos_;
                       } else {
                           recording_ = !recording_;
                       }
                   },
                   [&](const auto&) { expected = false; },
               },
               *decoded);
    if (!expected) {
        ++stats_.unexpected_frames;
        Received r = make_received(Received::Kind::kUnexpected, frame.command);
        r.message = *decoded;
        notify(std::move(r));
        return;
    }
    Received r = make_received(Received::Kind::kFrame, frame.command);
    r.message = *decoded;
    notify(std::move(r));
}

void GimbalModel::apply(const protocol::Control& control) {
    mode_ = control.mode;
    const auto limits = to_array(options_.limits);
    switch (control.mode) {
        case p::ControlMode::kSpeed:
            velocity_ = p::degrees_of(control.speed);
            speed_until_ = now_ + options_.speed_timeout;
            break;
        case p::ControlMode::kAngle:
            target_ = p::degrees_of(control.angle);
            for (std::size_t i = 0; i < 3; ++i) {
                target_[i] = std::clamp(target_[i], -limits[i], limits[i]);
            }
            break;
        case p::ControlMode::kCenter:
            target_ = {};
            break;
        case p::ControlMode::kLock:
            velocity_ = {};
            break;
    }
}

std::vector<std::uint8_t> to_bytes(std::span<const protocol::Frame> frames) {
    std::vector<std::uint8_t> out;
    for (const auto& f : frames) {
        out.insert(out.end(), f.bytes().begin(), f.bytes().end());
    }
    return out;
}

}  // namespace gport::sim
