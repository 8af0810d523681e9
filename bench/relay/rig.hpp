// What every scenario runs on: gport-sim's simulator draining the line at
// 115200 baud (in this process), the real gportd on it with its shipped
// request limits, gport-web with a control and a view token, and
// gport-mavlink (udpin on a free loopback port, vehicle 1, ground station
// 255), both relays on gportd's socket. Their logs are files in one
// temporary directory, kept with --keep-logs or after an error.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "../e2e/daemon_process.hpp"
#include "../e2e/line_sim.hpp"
#include "motion_watch.hpp"
#include "options.hpp"
#include "process.hpp"
#include "web_client.hpp"

namespace gport::bench::relay {

// Counts that only grow; a scenario reports what it added.
struct Marks {
    int web_drops = 0;      // "gportd not reachable" lines in gport-web's log
    int mavlink_drops = 0;  // "connection lost" lines in gport-mavlink's log
    std::uint64_t lease_endings = 0;
};

struct Exits {
    int gport_web = -1;  // exit statuses after SIGTERM (128 + signal when killed)
    int gport_mavlink = -1;
    int gportd = -1;
};

class Rig {
  public:
    // Starts everything and waits until both relays are connected to gportd
    // and gportd's line is open. Throws std::runtime_error naming the log.
    explicit Rig(const Options& options);
    ~Rig();
    Rig(const Rig&) = delete;
    Rig& operator=(const Rig&) = delete;

    LineSim& sim() { return *sim_; }
    const WebTarget& web() const { return web_target_; }
    unsigned mavlink_port() const { return mavlink_port_; }
    Marks marks() const;
    bool web_alive() { return web_->running(); }
    bool mavlink_alive() { return mavlink_->running(); }
    // SIGTERM to the relays, then gportd.
    Exits finish();
    void keep_logs() { dir_.keep(); }
    const std::string& dir() const { return dir_.path(); }

  private:
    void start_gportd(const Options& options);
    void start_web(const Options& options);
    void start_mavlink(const Options& options);

    testing::TempDir dir_{"bench-relay"};
    std::unique_ptr<LineSim> sim_;
    std::unique_ptr<DaemonProcess> gportd_;
    std::unique_ptr<MotionWatch> watch_;
    std::unique_ptr<DaemonProcess> web_;
    std::unique_ptr<DaemonProcess> mavlink_;
    WebTarget web_target_;
    unsigned mavlink_port_ = 0;
};

}  // namespace gport::bench::relay
