// Core: construction, start, reload and shutdown, and the events the parts
// raise. Commands are in core_commands.cpp, status in core_status.cpp.
#include "gport/daemon/core.hpp"

namespace gport::daemon {

namespace asio = boost::asio;
namespace gp = gport::protocol;
using namespace std::chrono_literals;

namespace {

constexpr auto kShutdownDrainLimit = 500ms;

}  // namespace

Core::Core(asio::io_context& io, const config::Config& config, std::shared_ptr<spdlog::logger> log)
    : io_(io),
      config_(config),
      log_(std::move(log)),
      started_(std::chrono::steady_clock::now()),
      arbiter_(AccessPolicy(config.access)),
      reader_(io, config.serial.device, log_,
              FrameReader::Handlers{
                  [this](const gp::Attitude& a, SteadyTime now, WallTime wall) {
                      on_attitude(a, now, wall);
                  },
                  [this](const gp::SettingsBlock& block) { settings_.on_report(block); },
                  [this] { settings_.on_ack(); }}),
      port_(
          io, config.serial, config.link,
          SerialPort::Handlers{[this](std::span<const std::uint8_t> bytes) { reader_.feed(bytes); },
                               [this] {
                                   reader_.reset();
                                   camera_.device_opened();
                                   monitor_.device_opened();
                               },
                               [this](const std::string& reason) {
                                   monitor_.device_closed("device closed: " + reason);
                               }},
          log_),
      monitor_(io, config.link.stale_after, [this](const LinkEvent& e) { on_link(e); }),
      motion_(io, config, port_, log_),
      settings_(io, config.requests, [this](const gp::Frame& f) { return send(f); }),
      camera_(config.camera, log_, [this](const gp::Frame& f) { return send(f); }) {
    settings_.on_changed([this](std::uint64_t client, const gp::SettingsBlock& before,
                                const gp::SettingsBlock& after) {
        log_->info("settings changed by client {}: {}", client, describe_change(before, after));
    });
}

void Core::start() {
    log_->info("gimbal device {} (keepalive {} Hz, stale after {} ms)", config_.serial.device,
               config_.keepalive.rate_hz, config_.link.stale_after.count());
    port_.start();
    reader_.start();
}

// The only state a reload touches. config_ keeps the keys as started: the
// motion keys live in motion_ from then on.
void Core::reload(const config::Config& config) {
    arbiter_.set_policy(AccessPolicy(config.access));
    motion_.reload(config);
    camera_.reload(config.camera);
}

void Core::add_link_listener(std::function<void(const LinkEvent&)> listener) {
    link_listeners_.push_back(std::move(listener));
}

// ---- events ------------------------------------------------------------------

void Core::on_attitude(const gp::Attitude& attitude, SteadyTime now, WallTime wall) {
    latest_ = AttitudeSample{++seq_, wall, now, attitude};
    monitor_.attitude_received(now);
    motion_.on_attitude(*latest_);  // braking: before the sample is published
    if (observer_ != nullptr) {
        observer_->on_attitude(*latest_);
    }
    motion_.on_attitude_published(*latest_);  // tracking: it may end a motion
}

void Core::on_link(const LinkEvent& event) {
    if (event.reason == LinkMonitor::kWaitingForFirstAttitude) {
        log_->debug("{}", event.reason);
    } else {
        log_->info("link {}: {}", to_string(event.state), event.reason);
    }
    motion_.on_link(event.state);  // down ends the motion; stale one that brakes by the attitude
    for (auto& listener : link_listeners_) {
        listener(event);
    }
    if (observer_ != nullptr) {
        observer_->on_link(event);
    }
}

// ---- shutdown -----------------------------------------------------------

void Core::shutdown(std::function<void()> done) {
    motion_.shutdown();
    stopping_ = true;
    settings_.abort_all(link_down());  // after stopping_: "gportd is shutting down"
    reader_.stop();
    port_.drain(kShutdownDrainLimit, [this, done = std::move(done)] {
        monitor_.stop();
        port_.stop();
        done();
    });
}

}  // namespace gport::daemon
