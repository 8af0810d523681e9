#include "core_impl.hpp"

#include <fmt/format.h>

#include <boost/asio/post.hpp>

namespace gport::daemon {

namespace asio = boost::asio;
namespace gp = gport::protocol;
using namespace std::chrono_literals;

namespace {

constexpr auto kLineQualityInterval = 10s;
constexpr auto kShutdownDrainLimit = 500ms;

Millis keepalive_period(double rate_hz) {
    return std::chrono::duration_cast<Millis>(std::chrono::duration<double>(1.0 / rate_hz));
}

std::string pid_of(const std::optional<ClientInfo>& client) {
    return client ? std::to_string(client->pid) : std::string("-");
}

}  // namespace

Core::Impl::Impl(asio::io_context& io, const config::Config& config,
                 std::shared_ptr<spdlog::logger> log)
    : access(config.access),
      io_(io),
      config_(config),
      log_(std::move(log)),
      started_(std::chrono::steady_clock::now()),
      port_(io, config.serial, config.link,
            SerialPort::Handlers{[this](std::span<const std::uint8_t> bytes) { on_bytes(bytes); },
                                 [this] {
                                     decoder_.reset();
                                     monitor_.device_opened();
                                 },
                                 [this](const std::string& reason) {
                                     monitor_.device_closed("device closed: " + reason);
                                 }},
            log_),
      monitor_(io, config.link.stale_after, [this](const LinkEvent& e) { on_link(e); }),
      keepalive_(
          io, keepalive_period(config.keepalive.rate_hz),
          [this](const gp::Control& c) { return send_control(c); },
          [this](const MotionEvent& e) { on_motion(e); }),
      settings_(io, config.requests, [this](const gp::Frame& f) { return send(f); }),
      quality_timer_(io),
      shutdown_timer_(io) {}

void Core::Impl::start() {
    log_->info("gimbal device {} (keepalive {} Hz, stale after {} ms)", config_.serial.device,
               config_.keepalive.rate_hz, config_.link.stale_after.count());
    port_.start();
    arm_quality_timer();
}

// ---- commands --------------------------------------------------------------

std::optional<CommandError> Core::Impl::check_access(const ClientInfo& client) const {
    if (!access.may_command(client)) {
        return CommandError{ErrorCode::kPermission,
                            fmt::format("permission denied: uid {} may only read "
                                        "(status, attitude, subscribe, unsubscribe)",
                                        client.uid)};
    }
    return std::nullopt;
}

std::optional<CommandError> Core::Impl::check_command(const ClientInfo& client) const {
    if (auto error = check_access(client)) {
        return error;
    }
    if (auto busy = held_by_other(client)) {
        return *busy;
    }
    if (!port_.is_open() || stopping_) {
        return link_down();
    }
    return std::nullopt;
}

std::optional<CommandError> Core::Impl::held_by_other(const ClientInfo& client) const {
    if (!controller_ || controller_->id == client.id) {
        return std::nullopt;
    }
    return CommandError{ErrorCode::kBusy, fmt::format("control is held by another client (pid {})",
                                                      controller_->pid)};
}

CommandError Core::Impl::link_down() const {
    return CommandError{
        ErrorCode::kLinkDown,
        fmt::format("gimbal link down: serial device {} is not open", config_.serial.device)};
}

bool Core::Impl::send(const gp::Frame& frame) {
    return !stopping_ && port_.send(frame);
}

// 0x85 frames are never refused for queue space: a stop goes next, and a
// newer position command replaces a waiting one (write_queue.hpp).
bool Core::Impl::send_control(const gp::Control& control) {
    const auto kind = control == gp::Control::stop() ? FrameKind::kStop : FrameKind::kMotion;
    return port_.send(gp::encode(control), kind);
}

Outcome<SpeedStarted> Core::Impl::speed(const ClientInfo& client, gp::Axes speed,
                                        std::optional<Millis> duration) {
    const auto max = config_.keepalive.max_duration;
    if (duration && (duration->count() < 1 || *duration > max)) {
        return CommandError{ErrorCode::kInvalidParams,
                            fmt::format("duration_ms = {} is out of range; allowed 1 to {}",
                                        duration->count(), max.count())};
    }
    if (auto error = check_command(client)) {
        return *error;
    }
    if (!send_control(gp::Control::speed_of(speed))) {
        return link_down();
    }
    return keepalive_.start(client, speed, duration.value_or(config_.keepalive.default_duration));
}

// Any client that may command may stop, whoever holds control: stopping is
// always safe. The motion ends whatever happens to the frame; a device that
// is closed owes the zero speed and gets it first when it reopens.
Outcome<Done> Core::Impl::stop(const ClientInfo& client) {
    if (auto error = check_access(client)) {
        return *error;
    }
    const bool queued = send_control(gp::Control::stop());
    keepalive_.end(EndReason::kStop, false);
    if (!queued) {
        return CommandError{
            ErrorCode::kLinkDown,
            fmt::format("gimbal link down: serial device {} is not open; zero speed will be "
                        "the first frame sent when it reopens",
                        config_.serial.device)};
    }
    return Done{};
}

Outcome<Done> Core::Impl::position(const ClientInfo& client, const gp::Control& control,
                                   MotionMode mode) {
    if (auto error = check_command(client)) {
        return *error;
    }
    if (!send_control(control)) {
        return link_down();
    }
    keepalive_.end(EndReason::kSuperseded, false);
    MotionEvent e;
    e.change = MotionChange::kStarted;
    e.mode = mode;
    e.owner = client;
    e.angle = control.angle;
    on_motion(e);
    return Done{};
}

Outcome<Done> Core::Impl::camera(const ClientInfo& client, gp::CameraAction action) {
    if (auto error = check_command(client)) {
        return *error;
    }
    if (!send(gp::encode(gp::Camera{action}))) {
        return CommandError{ErrorCode::kLinkDown,
                            fmt::format("gimbal link down: serial device {} takes no data "
                                        "({} frames wait for it)",
                                        config_.serial.device, SerialPort::kMaxQueuedFrames)};
    }
    log_->info("camera {} by pid {}",
               action == gp::CameraAction::kPhoto ? "photo" : "record toggle", client.pid);
    return Done{};
}

Outcome<std::optional<ClientInfo>> Core::Impl::acquire(const ClientInfo& client) {
    if (auto error = check_access(client)) {
        return *error;
    }
    if (auto busy = held_by_other(client)) {
        return *busy;
    }
    if (!controller_) {
        log_->info("control acquired by pid {}", client.pid);
    }
    controller_ = client;
    // Set first: an observer called from end() sees the new holder.
    const auto owner = keepalive_.owner();
    if (owner && owner->id != client.id) {
        keepalive_.end(EndReason::kPreempted, true);
    }
    return controller_;
}

Outcome<std::optional<ClientInfo>> Core::Impl::release(const ClientInfo& client) {
    if (controller_ && controller_->id != client.id) {
        return CommandError{ErrorCode::kBusy,
                            fmt::format("control is held by another client (pid {}); only it "
                                        "may release it",
                                        controller_->pid)};
    }
    if (controller_) {
        log_->info("control released by pid {}", client.pid);
        controller_.reset();
    }
    return controller_;
}

void Core::Impl::settings(const ClientInfo& client, std::optional<SettingsChange> change,
                          SettingsCallback done) {
    auto error = check_command(client);
    if (!error) {
        error = settings_.admit(client.id);
    }
    if (error) {
        asio::post(io_, [done = std::move(done), e = *error] { done(e); });
        return;
    }
    auto reply = [done = std::move(done)](Outcome<gp::SettingsBlock> r) {
        if (!r) {
            done(r.error());
            return;
        }
        done(Settings{r->dead_zone, r->follow_speed, r->inverted()});
    };
    if (change) {
        settings_.set(client.id, *change, std::move(reply));
    } else {
        settings_.get(client.id, std::move(reply));
    }
}

void Core::Impl::client_gone(const ClientInfo& client) {
    const auto owner = keepalive_.owner();
    if (owner && owner->id == client.id) {
        keepalive_.end(EndReason::kOwnerGone, true);  // the deadman
    }
    if (controller_ && controller_->id == client.id) {
        log_->info("control released: pid {} disconnected", client.pid);
        controller_.reset();
    }
}

void Core::Impl::client_closed(const ClientInfo& client) {
    settings_.forget(client.id);
    access.forget(client);
}

// ---- the read path -----------------------------------------------------------

void Core::Impl::on_bytes(std::span<const std::uint8_t> bytes) {
    const auto now = std::chrono::steady_clock::now();
    const auto wall = std::chrono::system_clock::now();
    decoder_.feed(bytes, [&](const gp::FrameView& frame) { on_frame(frame, now, wall); });
}

void Core::Impl::on_frame(const gp::FrameView& frame, SteadyTime now, WallTime wall) {
    auto message = gp::decode(frame);
    if (!message) {
        ++bad_messages_;
        log_->debug("ignoring frame from the gimbal: {}", message.error().message);
        return;
    }
    std::visit(
        [&](const auto& m) {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, gp::Attitude>) {
                on_attitude(m, now, wall);
            } else if constexpr (std::is_same_v<T, gp::SettingsReport>) {
                settings_.on_report(m.block);
            } else if constexpr (std::is_same_v<T, gp::SetSettingsAck>) {
                settings_.on_ack();
            } else {
                log_->debug("ignoring command 0x{:02X} from the gimbal", frame.command);
            }
        },
        *message);
}

void Core::Impl::on_attitude(const gp::Attitude& attitude, SteadyTime now, WallTime wall) {
    latest = AttitudeSample{++seq_, wall, now, attitude};
    monitor_.attitude_received(now);
    if (observer != nullptr) {
        observer->on_attitude(*latest);
    }
}

// ---- events ------------------------------------------------------------------

void Core::Impl::on_link(const LinkEvent& event) {
    log_->info("link {}: {}", to_string(event.state), event.reason);
    if (event.state == LinkState::kDown) {
        keepalive_.end(EndReason::kLinkDown, false);
    }
    for (auto& listener : link_listeners) {
        listener(event);
    }
    if (observer != nullptr) {
        observer->on_link(event);
    }
}

void Core::Impl::on_motion(const MotionEvent& event) {
    if (event.change == MotionChange::kEnded) {
        log_->info("motion ended ({}), owner pid {}",
                   event.reason ? to_string(*event.reason) : "unknown", pid_of(event.owner));
    } else {
        log_->info("motion {} ({}) by pid {}", to_string(event.change), to_string(event.mode),
                   pid_of(event.owner));
    }
    if (observer != nullptr) {
        observer->on_motion(event);
    }
}

// A noisy line is reported as one summary per interval, never per frame.
void Core::Impl::arm_quality_timer() {
    quality_timer_.expires_after(kLineQualityInterval);
    quality_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            report_line_quality();
            arm_quality_timer();
        }
    });
}

void Core::Impl::report_line_quality() {
    const auto& now = decoder_.stats();
    const auto crc = now.crc_errors - reported_.crc_errors;
    const auto header = now.header_errors - reported_.header_errors;
    const auto garbage = now.garbage_bytes - reported_.garbage_bytes;
    if (crc + header + garbage > 0) {
        log_->warn(
            "noisy line on {}: {} CRC errors, {} header errors, {} garbage bytes in the "
            "last {} s",
            config_.serial.device, crc, header, garbage,
            std::chrono::duration_cast<std::chrono::seconds>(kLineQualityInterval).count());
    }
    reported_ = now;
}

// ---- shutdown -----------------------------------------------------------

void Core::Impl::shutdown(std::function<void()> done) {
    keepalive_.end(EndReason::kShutdown, true);
    stopping_ = true;
    settings_.abort_all(CommandError{ErrorCode::kLinkDown, "gportd is shutting down"});
    quality_timer_.cancel();
    auto finished = std::make_shared<bool>(false);
    auto finish = [this, finished, done = std::move(done)] {
        if (std::exchange(*finished, true)) {
            return;
        }
        shutdown_timer_.cancel();
        monitor_.stop();
        port_.stop();
        done();
    };
    shutdown_timer_.expires_after(kShutdownDrainLimit);
    shutdown_timer_.async_wait([finish](boost::system::error_code ec) {
        if (!ec) {
            finish();
        }
    });
    // Posted to the loop (never to asio's system executor, another thread),
    // so that finish() does not run inside SerialPort's own completion.
    port_.when_drained([this, finish] { asio::post(io_, [finish] { finish(); }); });
}

}  // namespace gport::daemon
