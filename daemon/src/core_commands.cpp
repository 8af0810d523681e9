// Core's commands: each checks its parameters, then admit() (access and
// control by the Arbiter, then the device), then queues its frame; motion
// commands go to Motion for both their checks and their frames.
#include <fmt/format.h>

#include <boost/asio/post.hpp>

#include "gport/daemon/core.hpp"

namespace gport::daemon {

namespace asio = boost::asio;
namespace gp = gport::protocol;

// ---- checks and the device -----------------------------------------------------

std::optional<CommandError> Core::admit(const ClientInfo& client, Arbiter::Needs needs) const {
    if (auto refused = arbiter_.check(client, needs)) {  // access, then control
        return refused;
    }
    if (!device_ready()) {
        return link_down();
    }
    return std::nullopt;
}

CommandError Core::link_down(std::string_view consequence) const {
    return link_down_error(port_, stopping_, consequence);
}

std::optional<CommandError> Core::send(const gp::Frame& frame) {
    if (!stopping_ && port_.send(frame)) {
        return std::nullopt;
    }
    return link_down();
}

bool Core::may_command(const ClientInfo& client) const {
    return arbiter_.may_command(client);
}

// ---- commands ----------------------------------------------------------------

// Each motion command: its parameters (Motion), then admit(), then Motion
// sends it and runs the motion.
Outcome<SpeedStarted> Core::speed(const ClientInfo& client, gp::Axes speed,
                                  std::optional<Millis> duration, bool clamp,
                                  std::optional<Millis> lease) {
    auto request = motion_.check_speed(speed, duration, clamp, lease);
    if (!request) {
        return request.error();
    }
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    return motion_.speed(client, std::move(*request));
}

// Any client that may command may stop, whoever holds control: stopping is
// always safe. The motion ends whatever happens to the frame; a device that
// is closed owes the zero speed and gets it first when it reopens.
Outcome<Done> Core::stop(const ClientInfo& client) {
    if (auto refused = arbiter_.check(client, Arbiter::Needs::kAccess)) {
        return std::move(*refused);
    }
    if (!motion_.stop()) {
        return link_down(stopping_ ? ""
                                   : "zero speed will be the first frame sent when it reopens");
    }
    return Done{};
}

Outcome<AngleSent> Core::angle(const ClientInfo& client, gp::Axes angle, bool clamp,
                               MotionEndCallback on_end) {
    auto target = motion_.check_angle(angle, clamp);
    if (!target) {
        return target.error();
    }
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    return motion_.angle(client, std::move(*target), std::move(on_end));
}

Outcome<AngleSent> Core::center(const ClientInfo& client, MotionEndCallback on_end) {
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    return motion_.center(client, std::move(on_end));
}

Outcome<Done> Core::lock(const ClientInfo& client) {
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    return motion_.lock(client);
}

Outcome<Done> Core::photo(const ClientInfo& client) {
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    return camera_.photo(client.pid);
}

// The recording state is CameraGate's (assumed: the protocol cannot read it).
Outcome<RecordResult> Core::record(const ClientInfo& client, RecordRequest request) {
    if (auto invalid = camera_.check_record(request)) {
        return std::move(*invalid);
    }
    if (auto refused = admit(client, Arbiter::Needs::kAccessAndControl)) {
        return std::move(*refused);
    }
    return camera_.record(request, client.pid);
}

// ---- control -------------------------------------------------------------------

Outcome<std::optional<ClientInfo>> Core::acquire(const ClientInfo& client) {
    auto acquired = arbiter_.acquire(client, motion_.owner());
    if (!acquired) {
        return acquired.error();
    }
    if (acquired->newly_held) {
        log_->info("control acquired by pid {}", client.pid);
    }
    // The arbiter has recorded the new holder: an observer called from end()
    // sees it.
    if (acquired->preempts) {
        motion_.preempt();
    }
    return arbiter_.holder();
}

Outcome<std::optional<ClientInfo>> Core::release(const ClientInfo& client) {
    auto released = arbiter_.release(client);
    if (!released) {
        return released.error();
    }
    if (released.value()) {
        log_->info("control released by pid {}", client.pid);
    }
    return arbiter_.holder();
}

// The deadman (Motion::owner_gone), then control.
void Core::client_gone(const ClientInfo& client) {
    motion_.owner_gone(client);
    if (arbiter_.client_gone(client)) {
        log_->info("control released: pid {} disconnected", client.pid);
    }
}

void Core::client_closed(const ClientInfo& client) {
    settings_.forget(client.id);
    arbiter_.forget(client);
}

// ---- settings ------------------------------------------------------------------

void Core::get_settings(const ClientInfo& client, SettingsCallback done) {
    settings(client, std::nullopt, std::move(done));
}

void Core::set_settings(const ClientInfo& client, SettingsChange change, SettingsCallback done) {
    settings(client, change, std::move(done));
}

void Core::settings(const ClientInfo& client, std::optional<SettingsChange> change,
                    SettingsCallback done) {
    auto refused = admit(client, Arbiter::Needs::kAccessAndControl);
    if (!refused) {
        refused = settings_.admit(client.id);
    }
    if (refused) {
        asio::post(io_, [done = std::move(done), e = *refused] { done(e); });
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

}  // namespace gport::daemon
