#include "gport/daemon/core/vehicle_track.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace gport::daemon {
namespace {

using std::chrono::duration_cast;
using std::chrono::microseconds;
using std::chrono::nanoseconds;

constexpr double kEarthRadiusM = 6378137.0;  // WGS84's equatorial radius
constexpr double kMaxAltitudeM = 100000.0;
constexpr double kMinAltitudeM = -1000.0;
constexpr double kMaxSpeedMs = 300.0;  // per axis: no drone is faster
constexpr double kMaxYawRateDps = 3600.0;
constexpr double kMaxAccuracyM = 100000.0;
// SYSTEM_TIME's UTC: from 2020 (an autopilot without GPS time sends 0 or its
// build date) to 2100.
constexpr std::int64_t kMinUtcUs = 1577836800LL * 1000000;
constexpr std::int64_t kMaxUtcUs = 4102444800LL * 1000000;

CommandError invalid(std::string message) {
    return CommandError{ErrorCode::kInvalidParams, std::move(message)};
}

// The first value out of its range, as the error naming it and the range.
std::optional<CommandError> out_of_range(const char* name, double value, double min, double max) {
    if (std::isfinite(value) && value >= min && value <= max) {
        return std::nullopt;
    }
    return invalid(
        fmt::format("position.{} must be a number from {} to {}, got {}", name, min, max, value));
}

std::optional<CommandError> check_position(const VehiclePosition& p) {
    struct Field {
        const char* name;
        std::optional<double> value;
        double min, max;
    };
    const Field fields[] = {
        {"lat", p.lat_deg, -90, 90},
        {"lon", p.lon_deg, -180, 180},
        {"alt_msl_m", p.alt_msl_m, kMinAltitudeM, kMaxAltitudeM},
        {"alt_rel_m", p.alt_rel_m, -kMaxAltitudeM, kMaxAltitudeM},
        {"velocity_ned[0]", p.velocity_ned[0], -kMaxSpeedMs, kMaxSpeedMs},
        {"velocity_ned[1]", p.velocity_ned[1], -kMaxSpeedMs, kMaxSpeedMs},
        {"velocity_ned[2]", p.velocity_ned[2], -kMaxSpeedMs, kMaxSpeedMs},
        {"heading_deg", p.heading_deg, 0, 360},
        {"yaw_rate_dps", p.yaw_rate_dps, -kMaxYawRateDps, kMaxYawRateDps},
        {"h_acc_m", p.h_acc_m, 0, kMaxAccuracyM},
        {"v_acc_m", p.v_acc_m, 0, kMaxAccuracyM},
    };
    for (const auto& f : fields) {
        if (f.value) {
            if (auto error = out_of_range(f.name, *f.value, f.min, f.max)) {
                return error;
            }
        }
    }
    if (p.fix && (*p.fix < 0 || *p.fix > 8)) {
        return invalid(
            fmt::format("position.fix must be a GPS_FIX_TYPE from 0 to 8, got {}", *p.fix));
    }
    if (p.satellites && (*p.satellites < 0 || *p.satellites > 255)) {
        return invalid(
            fmt::format("position.satellites must be from 0 to 255, got {}", *p.satellites));
    }
    return std::nullopt;
}

std::int64_t median(std::vector<std::int64_t> values) {
    const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), mid, values.end());
    return *mid;
}

double seconds(SteadyTime::duration d) {
    return std::chrono::duration<double>(d).count();
}

std::string source_name(const ClientInfo& c) {
    return fmt::format("pid {}, uid {}", c.pid, c.uid);
}

}  // namespace

std::optional<CommandError> VehicleTrack::check(const VehicleReport& report) {
    if (!report.position && !report.time) {
        return invalid("publish_vehicle needs position, time or both");
    }
    if (report.position) {
        if (auto error = check_position(*report.position)) {
            return error;
        }
    }
    if (report.time && (report.time->utc_us < kMinUtcUs || report.time->utc_us > kMaxUtcUs)) {
        return invalid(fmt::format(
            "time.utc_us must be a UTC time from 2020 to 2100 in microseconds since 1970, got {} "
            "(an autopilot without GPS time sends 0: publish no time until it has one)",
            report.time->utc_us));
    }
    return std::nullopt;
}

std::optional<CommandError> VehicleTrack::publish(const ClientInfo& client,
                                                  const VehicleReport& report, SteadyTime now) {
    if (source_ && source_->id != client.id && now - source_seen_ < kSourceSilence) {
        ++status_.refused;
        return CommandError{ErrorCode::kBusy,
                            fmt::format("another client ({}) publishes the vehicle's state; one "
                                        "source at a time (taken over after {} s of silence)",
                                        source_name(*source_), kSourceSilence.count())};
    }
    if (boot_clock_restarted(report.position ? report.position->boot_ms : report.time->boot_ms,
                             now)) {
        reset();
    }
    if (report.position) {
        if (auto error = take_position(*report.position)) {
            ++status_.refused;
            return error;
        }
        observe_latency(report.position->boot_ms, now);
    }
    if (report.time) {
        if (auto error = take_time(*report.time)) {
            ++status_.refused;
            return error;
        }
        observe_latency(report.time->boot_ms, now);
    }
    ever_ = true;
    source_ = client;
    source_seen_ = now;
    ++status_.published;
    return std::nullopt;
}

std::optional<CommandError> VehicleTrack::check_order(std::uint32_t boot_ms,
                                                      std::optional<std::uint32_t> last,
                                                      const char* what) {
    if (!last || boot_ms > *last) {
        return std::nullopt;
    }
    if (*last - boot_ms > kRebootBackMs) {
        reset();  // the autopilot started again: its boot time did
        return std::nullopt;
    }
    return invalid(
        fmt::format("{}.boot_ms {} is not after the last one taken, {}: a sample out of "
                    "order or repeated (boot times must increase; one more than {} ms "
                    "back means the autopilot rebooted)",
                    what, boot_ms, *last, kRebootBackMs));
}

// A sample arriving more than kRebootBackMs after the clock mapping puts its
// boot time: the autopilot's boot clock started again, and its boot times
// have not yet passed the last one taken (it rebooted within about a second
// of it, as in a brown-out loop), or a sample was held up that long on its
// way. Either way the mapping, the UTC offsets and the position are no
// longer to be trusted.
bool VehicleTrack::boot_clock_restarted(std::uint32_t boot_ms, SteadyTime now) const {
    return !latencies_.empty() && now - steady_of(boot_ms) > Millis(kRebootBackMs);
}

std::optional<CommandError> VehicleTrack::take_position(const VehiclePosition& position) {
    const auto last = position_ ? std::optional(position_->boot_ms) : std::nullopt;
    if (auto error = check_order(position.boot_ms, last, "position")) {
        return error;
    }
    position_ = position;
    rebooted_ = false;
    return std::nullopt;
}

std::optional<CommandError> VehicleTrack::take_time(const VehicleTime& time) {
    const auto last = time_ ? std::optional(time_->boot_ms) : std::nullopt;
    if (auto error = check_order(time.boot_ms, last, "time")) {
        return error;
    }
    time_ = time;
    utc_offsets_us_.push_back(time.utc_us - std::int64_t{time.boot_ms} * 1000);
    if (utc_offsets_us_.size() > kUtcSamples) {
        utc_offsets_us_.pop_front();
    }
    return std::nullopt;
}

void VehicleTrack::reset() {
    position_.reset();
    time_.reset();
    latencies_.clear();
    utc_offsets_us_.clear();
    rebooted_ = true;
    ++status_.resets;
}

// A sample's offset aged to an instant t is offset + kAgingPpm x (t -
// arrival): what it is kept as, offset - kAgingPpm x arrival, differs from
// that by the same kAgingPpm x t for every sample, so their order never
// changes and one minimum serves every instant.
namespace {
nanoseconds aging(SteadyTime t) {
    return nanoseconds(duration_cast<nanoseconds>(t.time_since_epoch()).count() /
                       (1'000'000 / VehicleTrack::kAgingPpm));
}
}  // namespace

void VehicleTrack::observe_latency(std::uint32_t boot_ms, SteadyTime now) {
    // A minimum queue: a sample no less delayed (once aged) than a newer one
    // can never be the window's least delayed, so the front is the minimum
    // and each report costs O(1) amortised, whatever the publisher sends.
    const auto offset = now.time_since_epoch() - duration_cast<nanoseconds>(Millis(boot_ms));
    const auto kept = offset - aging(now);
    while (!latencies_.empty() && latencies_.back().second >= kept) {
        latencies_.pop_back();
    }
    latencies_.emplace_back(now, kept);
    while (latencies_.size() > 1 && now - latencies_.front().first > kOffsetWindow) {
        latencies_.pop_front();
    }
}

// Through the least delayed sample aged to the newest sample's arrival.
SteadyTime VehicleTrack::steady_of(std::uint32_t boot_ms) const {
    const auto offset = latencies_.front().second + aging(latencies_.back().first);
    return SteadyTime(duration_cast<SteadyTime::duration>(offset + Millis(boot_ms)));
}

std::optional<std::int64_t> VehicleTrack::utc_at(SteadyTime instant) const {
    if (utc_offsets_us_.empty() || latencies_.empty()) {
        return std::nullopt;
    }
    // The boot time at the instant, in microseconds, through the latency map.
    const auto boot_zero = steady_of(0);
    const auto boot_us = duration_cast<microseconds>(instant - boot_zero).count();
    return boot_us + median({utc_offsets_us_.begin(), utc_offsets_us_.end()});
}

void VehicleTrack::stamp_position(VehicleStamp& stamp, SteadyTime instant) const {
    if (!position_) {
        stamp.why =
            rebooted_ ? "no position since the autopilot rebooted" : "no position published yet";
        return;
    }
    const auto& p = *position_;
    const auto age = std::max(instant - steady_of(p.boot_ms), SteadyTime::duration::zero());
    stamp.age = duration_cast<Millis>(age);
    if (age > config_.max_position_age) {
        stamp.why = fmt::format(
            "the newest position is {:.3f} s old at the capture "
            "(camera.max_position_age_ms is {})",
            seconds(age), config_.max_position_age.count());
        return;
    }
    if (p.fix && *p.fix < 3) {
        stamp.why = fmt::format("no 3D GPS fix (GPS_FIX_TYPE {})", *p.fix);
        return;
    }
    const double t = seconds(age);
    const auto [vn, ve, vd] = p.velocity_ned;
    // Carried on an arc when the yaw rate is known (the velocity turning with
    // the vehicle), else straight.
    double dn = vn * t;
    double de = ve * t;
    if (p.yaw_rate_dps && std::abs(*p.yaw_rate_dps) > 1e-3) {
        const double w = *p.yaw_rate_dps * std::numbers::pi / 180.0;
        const double s = std::sin(w * t) / w;
        const double c = (1.0 - std::cos(w * t)) / w;
        dn = vn * s - ve * c;
        de = ve * s + vn * c;
    }
    const double lat_rad = p.lat_deg * std::numbers::pi / 180.0;
    stamp.lat_deg =
        std::clamp(p.lat_deg + dn / kEarthRadiusM * 180.0 / std::numbers::pi, -90.0, 90.0);
    double lon = p.lon_deg + de / (kEarthRadiusM * std::max(std::cos(lat_rad), 1e-6)) * 180.0 /
                                 std::numbers::pi;
    stamp.lon_deg = std::remainder(lon, 360.0);  // near a pole a carry spans many turns
    stamp.alt_msl_m = p.alt_msl_m - vd * t;
    if (p.alt_rel_m) {
        stamp.alt_rel_m = *p.alt_rel_m - vd * t;
    }
    stamp.velocity_ned = p.velocity_ned;
    if (p.heading_deg) {
        const double turned = *p.heading_deg + p.yaw_rate_dps.value_or(0) * t;
        stamp.heading_deg = std::fmod(std::fmod(turned, 360.0) + 360.0, 360.0);
    }
    if (p.h_acc_m) {
        stamp.h_acc_m = *p.h_acc_m + t * std::hypot(vn, ve);
    }
    if (p.v_acc_m) {
        stamp.v_acc_m = *p.v_acc_m + t * std::abs(vd);
    }
    stamp.fix = p.fix;
    stamp.satellites = p.satellites;
    stamp.tagged = true;
}

std::optional<VehicleStamp> VehicleTrack::at(SteadyTime instant) const {
    if (!ever_) {
        return std::nullopt;
    }
    VehicleStamp stamp;
    stamp_position(stamp, instant);
    stamp.utc_us = utc_at(instant);
    return stamp;
}

void VehicleTrack::client_closed(const ClientInfo& client) {
    if (source_ && source_->id == client.id) {
        source_.reset();
    }
}

std::optional<VehicleStatus> VehicleTrack::status(SteadyTime now) const {
    if (!ever_ && status_.refused == 0) {
        return std::nullopt;
    }
    VehicleStatus s = status_;
    s.source = source_;
    s.position = position_;
    if (position_ && !latencies_.empty()) {
        s.position_age = duration_cast<Millis>(now - steady_of(position_->boot_ms));
    }
    s.utc_known = !utc_offsets_us_.empty();
    if (time_ && !latencies_.empty()) {
        s.time_age = duration_cast<Millis>(now - steady_of(time_->boot_ms));
    }
    return s;
}

}  // namespace gport::daemon
