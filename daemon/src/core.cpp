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
    : config_(config),
      log_(std::move(log)),
      started_(std::chrono::steady_clock::now()),
      arbiter_(AccessPolicy(config.access)),
      link_(io, config, log_,
            GimbalLink::Handlers{
                FrameReader::Handlers{
                    [this](const gp::Attitude& a, SteadyTime now, WallTime wall) {
                        on_attitude(a, now, wall);
                    },
                    [this](const gp::SettingsBlock& block) { settings_.on_report(block); },
                    [this] { settings_.on_ack(); }},
                [this] { camera_.device_opened(); }, [this](const LinkEvent& e) { on_link(e); }}),
      motion_(io, config, link_, log_, latest_),
      settings_(
          io, config.requests, [this](const gp::Frame& f) { return link_.send(f); }, log_),
      camera_(config.camera, log_, [this](const gp::Frame& f) { return link_.send(f); }),
      vehicle_(config.camera) {}

void Core::start() {
    log_->info("gimbal device {} (keepalive {} Hz, stale after {} ms)", config_.serial.device,
               config_.keepalive.rate_hz, config_.link.stale_after.count());
    link_.start();
}

// The only state a reload touches. config_ keeps the keys as started: the
// motion keys live in motion_ from then on.
void Core::reload(const config::Config& config) {
    arbiter_.set_policy(AccessPolicy(config.access));
    motion_.reload(config);
    camera_.reload(config.camera);
    vehicle_.reload(config.camera);
}

void Core::add_link_listener(std::function<void(const LinkEvent&)> listener) {
    link_listeners_.push_back(std::move(listener));
}

// ---- events ------------------------------------------------------------------

void Core::on_attitude(const gp::Attitude& attitude, SteadyTime now, WallTime wall) {
    latest_ = AttitudeSample{++seq_, wall, now, attitude};
    link_.attitude_received(now);
    motion_.on_attitude();  // braking: before the sample is published
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

// ---- status: the figures of every part, gathered for the client API -------

Status Core::status() const {
    Status s;
    link_.report(s);
    const auto now = std::chrono::steady_clock::now();
    s.uptime = std::chrono::duration_cast<Millis>(now - started_);
    if (latest_) {
        s.attitude_age = std::chrono::duration_cast<Millis>(now - latest_->received);
    }
    auto& c = s.counters;
    c.attitude_frames = seq_;
    c.keepalive_frames = motion_.keepalive_frames();
    c.motion_updates = motion_.updates();
    c.settings_timeouts = settings_.timeouts();
    s.motion = motion_.status();
    s.controller = arbiter_.holder();
    s.recording = camera_.recording();
    s.camera = camera_.status();
    s.vehicle = vehicle_.status(now);
    return s;
}

// ---- shutdown -----------------------------------------------------------

void Core::shutdown(std::function<void()> done) {
    motion_.shutdown();
    link_.shutdown(kShutdownDrainLimit, std::move(done));
    settings_.abort_all(link_.link_down());  // after shutdown(): "gportd is shutting down"
}

}  // namespace gport::daemon
