// Core: construction, start, reload and shutdown; the read path (bytes to
// frames to events) and the events the parts raise. Commands are in
// core_commands.cpp, status in core_status.cpp.
#include "gport/daemon/core.hpp"

#include <fmt/format.h>

#include <boost/asio/post.hpp>

namespace gport::daemon {

namespace asio = boost::asio;
namespace gp = gport::protocol;
using namespace std::chrono_literals;

namespace {

constexpr auto kLineQualityInterval = 10s;
constexpr auto kShutdownDrainLimit = 500ms;

// "dead_zone 10 -> 5, inverted no -> yes": the values that changed, or that
// nothing did.
std::string settings_change(const gp::SettingsBlock& before, const gp::SettingsBlock& after) {
    std::string out;
    const auto add = [&](const char* name, const std::string& from, const std::string& to) {
        if (from != to) {
            out += fmt::format("{}{} {} -> {}", out.empty() ? "" : ", ", name, from, to);
        }
    };
    add("dead_zone", std::to_string(before.dead_zone), std::to_string(after.dead_zone));
    add("follow_speed", std::to_string(before.follow_speed), std::to_string(after.follow_speed));
    add("inverted", before.inverted() ? "yes" : "no", after.inverted() ? "yes" : "no");
    return out.empty() ? "nothing changed (the values asked for were already set)" : out;
}

}  // namespace

Core::Core(asio::io_context& io, const config::Config& config, std::shared_ptr<spdlog::logger> log)
    : io_(io),
      config_(config),
      log_(std::move(log)),
      started_(std::chrono::steady_clock::now()),
      arbiter_(AccessPolicy(config.access)),
      port_(io, config.serial, config.link,
            SerialPort::Handlers{[this](std::span<const std::uint8_t> bytes) { on_bytes(bytes); },
                                 [this] {
                                     decoder_.reset();
                                     // The gimbal may have been power-cycled.
                                     recording_ = RecordingState::kUnknown;
                                     monitor_.device_opened();
                                 },
                                 [this](const std::string& reason) {
                                     monitor_.device_closed("device closed: " + reason);
                                 }},
            log_),
      monitor_(io, config.link.stale_after, [this](const LinkEvent& e) { on_link(e); }),
      motion_(io, config, port_, log_),
      settings_(io, config.requests,
                [this](const gp::Frame& f) -> std::optional<CommandError> {
                    if (send(f)) {
                        return std::nullopt;
                    }
                    return link_down();
                }),
      quality_timer_(io),
      shutdown_timer_(io),
      camera_(config.camera) {
    settings_.on_changed([this](std::uint64_t client, const gp::SettingsBlock& before,
                                const gp::SettingsBlock& after) {
        log_->info("settings changed by client {}: {}", client, settings_change(before, after));
    });
}

void Core::start() {
    log_->info("gimbal device {} (keepalive {} Hz, stale after {} ms)", config_.serial.device,
               config_.keepalive.rate_hz, config_.link.stale_after.count());
    port_.start();
    arm_quality_timer();
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

// ---- the read path -----------------------------------------------------------

void Core::on_bytes(std::span<const std::uint8_t> bytes) {
    const auto now = std::chrono::steady_clock::now();
    const auto wall = std::chrono::system_clock::now();
    decoder_.feed(bytes, [&](const gp::FrameView& frame) { on_frame(frame, now, wall); });
}

void Core::on_frame(const gp::FrameView& frame, SteadyTime now, WallTime wall) {
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

void Core::on_attitude(const gp::Attitude& attitude, SteadyTime now, WallTime wall) {
    latest_ = AttitudeSample{++seq_, wall, now, attitude};
    monitor_.attitude_received(now);
    motion_.on_attitude(*latest_);  // braking: before the sample is published
    if (observer_ != nullptr) {
        observer_->on_attitude(*latest_);
    }
    motion_.on_attitude_published(*latest_);  // tracking: it may end a motion
}

// ---- events ------------------------------------------------------------------

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

// A noisy line is reported as one summary per interval, never per frame.
void Core::arm_quality_timer() {
    quality_timer_.expires_after(kLineQualityInterval);
    quality_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            report_line_quality();
            arm_quality_timer();
        }
    });
}

void Core::report_line_quality() {
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

void Core::shutdown(std::function<void()> done) {
    motion_.shutdown();
    stopping_ = true;
    settings_.abort_all(link_down());  // after stopping_: "gportd is shutting down"
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
