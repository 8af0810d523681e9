// The ground station's floods run on a thread of their own, paced to their
// rate (datagrams a second, averaged: a late tick sends what it owes); the
// vehicle's probe sends its heartbeat once a second and reads what
// gport-mavlink sends it, as an autopilot would.
#include <fmt/format.h>

#include <array>
#include <atomic>
#include <chrono>
#include <thread>

#include "../e2e/posix.hpp"
#include "gport/mavlink/enums.hpp"
#include "mavlink_link.hpp"
#include "scenarios.hpp"

namespace gport::bench::relay {
namespace {

constexpr float kProbeYawRate = 0.1F;  // rad/s, about 5.7 °/s
constexpr std::int64_t kHeartbeatNs = 1'000'000'000;

// A ground station flooding gport-mavlink ("gcs-camera" or "gcs-angles").
class MavlinkFlood {
  public:
    MavlinkFlood(unsigned port, const std::string& flood)
        : port_(port),
          camera_(flood == "gcs-camera"),
          rate_(flood == "gcs-camera"   ? 2000
                : flood == "gcs-angles" ? 200
                                        : 0) {
        if (rate_ > 0) {
            thread_ = std::thread([this] { run(); });
        }
    }
    ~MavlinkFlood() { stop(); }
    MavlinkFlood(const MavlinkFlood&) = delete;
    MavlinkFlood& operator=(const MavlinkFlood&) = delete;

    void stop() {
        stop_ = true;
        if (thread_.joinable()) {
            thread_.join();
        }
    }
    std::uint64_t sent() const { return sent_.load(); }
    std::string acks() const {
        if (!camera_) {
            return "";
        }
        return fmt::format("acks {} accepted, {} temporarily rejected, {} denied, {} other",
                           acks_[0].load(), acks_[1].load(), acks_[2].load(), acks_[3].load());
    }

  private:
    // IMAGE_START_CAPTURE (one photo), DIGICAM_CONTROL (shot), video start,
    // video stop in turn; or one angle target, always the same (a manager
    // holding a target, which gport-mavlink's change filter sends once).
    gm::Message next(std::uint64_t i) const {
        if (!camera_) {
            return angle_target(0, -10, 20);
        }
        switch (i % 4) {
            case 0:
                return camera_command(gm::mav_cmd::kImageStartCapture, 2, 1);
            case 1:
                return camera_command(gm::mav_cmd::kDoDigicamControl, 4, 1);
            case 2:
                return camera_command(gm::mav_cmd::kVideoStartCapture);
            default:
                return camera_command(gm::mav_cmd::kVideoStopCapture);
        }
    }
    void count(const gm::Message& message) {
        if (const auto* ack = std::get_if<gm::CommandAck>(&message)) {
            ++acks_[std::min<std::size_t>(ack->result, 3)];
        }
    }
    void run() {
        MavlinkPeer gcs(port_, kGroundStation, kGcsComponent);
        const auto period = static_cast<std::int64_t>(1e9 / rate_);
        std::int64_t due = now_ns();
        for (std::uint64_t i = 0; !stop_; ++i) {
            gcs.send(next(i));
            ++sent_;
            due += period;
            const auto now = now_ns();
            if (due > now) {
                std::this_thread::sleep_for(std::chrono::nanoseconds(due - now));
            } else if (now - due > 100'000'000) {
                due = now;  // far behind (descheduled): do not burst to catch up
            }
            if (i % 16 == 0) {
                gcs.drain([this](const gm::Message& m, std::uint8_t) { count(m); });
            }
        }
    }

    unsigned port_;
    bool camera_;
    double rate_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> sent_{0};
    std::array<std::atomic<std::uint64_t>, 4> acks_{};
    std::thread thread_;
};

}  // namespace

ScenarioResult run_mavlink_scenario(Rig& rig, const Options& options, const Scenario& scenario) {
    ScenarioResult result;
    result.scenario = scenario;
    MavlinkPeer vehicle(rig.mavlink_port(), kVehicle, gm::mav_comp_id::kAutopilot1);
    const Marks before = rig.marks();
    MavlinkFlood flood(rig.mavlink_port(), scenario.flood);
    std::this_thread::sleep_for(std::chrono::duration<double>(options.flood_seconds));
    const std::uint64_t sent = flood.sent();
    const auto start = now_ns();
    std::int64_t next_heartbeat = 0;
    ProbeHooks hooks;
    hooks.start_motion = [&] { vehicle.send(yaw_rate(kProbeYawRate)); };
    hooks.send_stop = [&](int) { vehicle.send(yaw_rate(0)); };
    hooks.idle = [&] {
        if (now_ns() >= next_heartbeat) {
            vehicle.send(autopilot_heartbeat());
            next_heartbeat = now_ns() + kHeartbeatNs;
        }
        vehicle.drain();
    };
    result.probe = run_probe(rig.sim(), options.stops, options.spacing_ms, hooks);
    const double seconds = static_cast<double>(now_ns() - start) / 1e9;
    flood.stop();
    if (flood.sent() > 0) {
        result.flood_rate =
            fmt::format("{:.0f} datagrams/s", static_cast<double>(flood.sent() - sent) / seconds);
        result.notes = flood.acks();
    } else {
        result.flood_rate = "-";
    }
    const Marks after = rig.marks();
    result.lease_endings = after.lease_endings - before.lease_endings;
    result.relay_drops = after.mavlink_drops - before.mavlink_drops;
    result.relay_alive = rig.mavlink_alive();
    return result;
}

}  // namespace gport::bench::relay
