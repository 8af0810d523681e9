// The vehicle's state in gportd (docs/api.md, "The vehicle"): what one
// trusted source publishes (positions with their velocity, accuracy and the
// autopilot's boot time; SYSTEM_TIME's UTC), checked, and the vehicle at any
// instant of the companion's steady clock — a capture's.
//
// The autopilot's clock meets the companion's through the samples
// themselves: each arrives some latency after its boot time, so the
// smallest (arrival - boot time) seen in the last kOffsetWindow maps boot
// time onto the steady clock (the fastest sample's latency is the floor of
// the others'), each sample's counted kAgingPpm of its age against it: the
// two crystals drift apart, and where the autopilot's runs slow the least
// delayed sample of a plain window would be its oldest, the map lagging by
// the drift times the window (4.5-8.9 ms against ArduCopter SITL, whose
// clock fell 149-296 ppm behind: docs/performance.md). UTC is the
// autopilot's: the median of the last kUtcSamples SYSTEM_TIME offsets
// (utc - boot time, taken at one instant on the autopilot, so no transit
// delay enters it) added to the boot time at the instant. Neither depends
// on the companion's wall clock, so a stepped clock moves nothing.
//
// A position is carried to the instant with its velocity (on an arc when a
// yaw rate is published), never further than camera.max_position_age_ms;
// its accuracy grows by age × speed. No GPS 3D fix, or too old: untagged.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

#include "gport/config/config.hpp"
#include "gport/daemon/outcome.hpp"
#include "gport/daemon/vehicle.hpp"

namespace gport::daemon {

class VehicleTrack {
  public:
    static constexpr auto kOffsetWindow = std::chrono::seconds(30);
    // Above any crystal's drift (an autopilot's about ±50 ppm; SITL's under
    // load up to ~300): 1 ms per second of a sample's age.
    static constexpr std::int64_t kAgingPpm = 1000;
    static constexpr std::size_t kUtcSamples = 9;
    // A boot time this far behind the newest: the autopilot rebooted (the
    // track starts again); less: a sample out of order, refused.
    static constexpr std::uint32_t kRebootBackMs = 1000;
    // A source silent this long may be replaced by another.
    static constexpr auto kSourceSilence = std::chrono::seconds(2);

    explicit VehicleTrack(const config::CameraConfig& config) : config_(config) {}
    void reload(const config::CameraConfig& config) { config_ = config; }
    Millis shutter_delay() const { return config_.shutter_delay; }

    // The values' ranges (kInvalidParams naming the field and what is
    // allowed); no state involved.
    static std::optional<CommandError> check(const VehicleReport& report);
    // Takes a report that passed check() from a client allowed to publish,
    // received at `now`; refuses one out of order or from a second source.
    std::optional<CommandError> publish(const ClientInfo& client, const VehicleReport& report,
                                        SteadyTime now);
    // A report refused before publish() (access, values): counted.
    void refused() { ++status_.refused; }
    void client_closed(const ClientInfo& client);

    // The vehicle at `instant`; nullopt when nothing was ever published.
    std::optional<VehicleStamp> at(SteadyTime instant) const;
    std::optional<VehicleStatus> status(SteadyTime now) const;

  private:
    std::optional<CommandError> take_position(const VehiclePosition& position);
    std::optional<CommandError> take_time(const VehicleTime& time);
    // A boot time behind `last`: true when it means a reboot (the track was
    // reset); an error when it is a sample out of order.
    std::optional<CommandError> check_order(std::uint32_t boot_ms,
                                            std::optional<std::uint32_t> last, const char* what);
    void reset();
    bool boot_clock_restarted(std::uint32_t boot_ms, SteadyTime now) const;
    void observe_latency(std::uint32_t boot_ms, SteadyTime now);
    // The steady instant of a boot time; needs a latency sample.
    SteadyTime steady_of(std::uint32_t boot_ms) const;
    std::optional<std::int64_t> utc_at(SteadyTime instant) const;
    void stamp_position(VehicleStamp& stamp, SteadyTime instant) const;

    config::CameraConfig config_;
    bool ever_ = false;
    std::optional<ClientInfo> source_;
    SteadyTime source_seen_{};
    std::optional<VehiclePosition> position_;
    std::optional<VehicleTime> time_;
    // (arrival, offset - its aging at arrival): increasing, so the front is
    // the least delayed once aged (observe_latency).
    std::deque<std::pair<SteadyTime, std::chrono::nanoseconds>> latencies_;
    std::deque<std::int64_t> utc_offsets_us_;  // utc - boot time
    VehicleStatus status_;                     // its counters
    bool rebooted_ = false;                    // since the last reset, no position yet
};

}  // namespace gport::daemon
