// Test fixture: the daemon core and the simulated gimbal on one io_context,
// talking over a real pseudo-terminal. The simulator's trace tells what
// reached the "gimbal"; an observer records what the core published.
#pragma once

#include <gtest/gtest.h>
#include <spdlog/sinks/null_sink.h>
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gport/daemon/core.hpp"
#include "gport/sim/simulator.hpp"

namespace gport::testing {

using namespace std::chrono_literals;
using Json = nlohmann::json;

struct Recorder : daemon::CoreObserver {
    std::vector<daemon::AttitudeSample> attitude;
    std::vector<daemon::LinkEvent> links;
    std::vector<daemon::MotionEvent> motions;
    void on_attitude(const daemon::AttitudeSample& s) override { attitude.push_back(s); }
    void on_link(const daemon::LinkEvent& e) override { links.push_back(e); }
    void on_motion(const daemon::MotionEvent& e) override { motions.push_back(e); }
};

inline std::shared_ptr<spdlog::logger> quiet_logger() {
    return std::make_shared<spdlog::logger>("test",
                                            std::make_shared<spdlog::sinks::null_sink_st>());
}

// Fast timings so tests finish quickly; behaviour is the same as defaults.
inline config::Config test_config(const std::string& device) {
    config::Config c;
    c.serial.device = device;
    c.link.stale_after = 300ms;
    c.link.reconnect_initial = 50ms;
    c.link.reconnect_max = 200ms;
    c.requests.timeout = 150ms;
    c.requests.retries = 1;
    // No camera limit (beyond what the config file allows): the stop tests
    // flood the line with photos (CameraGate has tests of its own).
    c.camera.max_commands_per_s = 1e9;
    return c;
}

class CoreFixture : public ::testing::Test {
  protected:
    // Starts the simulator with the options, then the core on its device.
    void start(sim::SimOptions options = {}, std::function<void(config::Config&)> tweak = {}) {
        options.trace = [this](const std::string& line) { trace.push_back(Json::parse(line)); };
        simulator = std::make_unique<sim::PtySimulator>(io, std::move(options));
        auto cfg = test_config(simulator->device_path());
        if (tweak) {
            tweak(cfg);
        }
        core = std::make_unique<daemon::Core>(io, cfg, logger);
        core->set_observer(&recorder);
        core->start();
    }

    void TearDown() override {
        if (core) {
            bool done = false;
            core->shutdown([&] { done = true; });
            run_until([&] { return done; }, 5s);
        }
        if (simulator) {
            simulator->stop();
        }
        io.poll();
    }

    // Runs the loop until pred holds; false on timeout.
    bool run_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout = 10s) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (!pred()) {
            if (std::chrono::steady_clock::now() >= deadline) {
                return false;
            }
            io.run_for(5ms);
        }
        return true;
    }

    void run_for(std::chrono::milliseconds d) {
        const auto deadline = std::chrono::steady_clock::now() + d;
        while (std::chrono::steady_clock::now() < deadline) {
            io.run_for(5ms);
        }
    }

    bool link_up() { return core->status().link == daemon::LinkState::kUp; }

    // Speed frames (mode speed) the gimbal received, as raw [roll,pitch,yaw].
    std::vector<Json> speed_frames() const {
        std::vector<Json> out;
        for (const auto& t : trace) {
            if (t.value("cmd", "") == "0x85" && t.value("mode", "") == "speed") {
                out.push_back(t["speed"]);
            }
        }
        return out;
    }

    std::size_t zero_speed_frames() const {
        std::size_t n = 0;
        for (const auto& s : speed_frames()) {
            n += s == Json::array({0, 0, 0}) ? 1 : 0;
        }
        return n;
    }

    std::vector<Json> trace_of(const std::string& cmd) const {
        std::vector<Json> out;
        for (const auto& t : trace) {
            if (t.value("cmd", "") == cmd) {
                out.push_back(t);
            }
        }
        return out;
    }

    std::size_t frames_with(const std::string& cmd) const {
        std::size_t n = 0;
        for (const auto& t : trace) {
            n += t.value("cmd", "") == cmd ? 1 : 0;
        }
        return n;
    }

    boost::asio::io_context io;
    std::shared_ptr<spdlog::logger> logger = quiet_logger();  // the core's, set before start()
    std::unique_ptr<sim::PtySimulator> simulator;
    std::unique_ptr<daemon::Core> core;
    Recorder recorder;
    std::vector<Json> trace;
    daemon::ClientInfo alice{1, 1001, 1001, 1001, {}};
    daemon::ClientInfo bob{2, 1002, 1002, 1002, {}};
};

}  // namespace gport::testing
