// Core's commands: each checks its parameters, then admit() (access and
// control by the Arbiter, then the device), then queues its frame; motion
// commands go to Motion for both their checks and their frames.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gport/daemon/core.hpp"

namespace gport::daemon {

namespace gp = gport::protocol;

namespace {

// "1001, 1002", or "none".
std::string listed(const std::vector<uid_t>& uids) {
    return uids.empty() ? std::string("none") : fmt::format("{}", fmt::join(uids, ", "));
}

}  // namespace

// ---- checks and the device -----------------------------------------------------

std::optional<CommandError> Core::admit(const ClientInfo& client, Arbiter::Needs needs) const {
    if (auto refused = arbiter_.check(client, needs)) {  // access, then control
        return refused;
    }
    if (!link_.ready()) {
        return link_.link_down();
    }
    return std::nullopt;
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
    return admitted(client, [&] { return motion_.speed(client, std::move(*request)); });
}

// Any client that may command may stop, whoever holds control: stopping is
// always safe. The motion ends whatever happens to the frame; a device that
// is closed owes the zero speed and gets it first when it reopens.
Outcome<Done> Core::stop(const ClientInfo& client) {
    if (auto refused = arbiter_.check(client, Arbiter::Needs::kAccess)) {
        return std::move(*refused);
    }
    if (!motion_.stop()) {
        return link_.link_down(
            link_.stopping() ? "" : "zero speed will be the first frame sent when it reopens");
    }
    return Done{};
}

Outcome<AngleSent> Core::angle(const ClientInfo& client, gp::Axes angle, bool clamp,
                               MotionEndCallback on_end) {
    auto target = motion_.check_angle(angle, clamp);
    if (!target) {
        return target.error();
    }
    return admitted(client,
                    [&] { return motion_.angle(client, std::move(*target), std::move(on_end)); });
}

Outcome<AngleSent> Core::center(const ClientInfo& client, MotionEndCallback on_end) {
    return admitted(client, [&] { return motion_.center(client, std::move(on_end)); });
}

Outcome<Done> Core::lock(const ClientInfo& client) {
    return admitted(client, [&] { return motion_.lock(client); });
}

// The camera frame was queued last: its last byte is due when the line has
// carried everything queued so far.
CaptureMoment Core::capture_moment() {
    CaptureMoment moment;
    moment.on_wire = link_.port().due_on_wire();
    moment.instant = moment.on_wire + vehicle_.shutter_delay();
    moment.vehicle = vehicle_.at(moment.instant);
    return moment;
}

Outcome<CaptureMoment> Core::photo(const ClientInfo& client) {
    if (auto sent = admitted(client, [&] { return camera_.photo(client.pid); }); !sent) {
        return sent.error();
    }
    return capture_moment();
}

// The recording state is CameraGate's (assumed: the protocol cannot read it).
Outcome<RecordResult> Core::record(const ClientInfo& client, RecordRequest request) {
    if (auto invalid = camera_.check_record(request)) {
        return std::move(*invalid);
    }
    auto result = admitted(client, [&] { return camera_.record(request, client.pid); });
    if (result && result->sent) {
        result->moment = capture_moment();
    }
    return result;
}

// Values, then who may publish, then the track's own order and source.
Outcome<Done> Core::publish_vehicle(const ClientInfo& client, const VehicleReport& report) {
    if (auto invalid = VehicleTrack::check(report)) {
        vehicle_.refused();
        return std::move(*invalid);
    }
    if (!arbiter_.policy().may_publish_vehicle(client)) {
        vehicle_.refused();
        return CommandError{
            ErrorCode::kPermission,
            fmt::format("permission denied: uid {} may not publish the vehicle's state (it stamps "
                        "every capture); allowed: root, gportd's own user and "
                        "access.vehicle_uids ({})",
                        client.uid, listed(arbiter_.policy().vehicle_uids()))};
    }
    if (auto refused = vehicle_.publish(client, report, std::chrono::steady_clock::now())) {
        return std::move(*refused);
    }
    return Done{};
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
    vehicle_.client_closed(client);
    arbiter_.forget(client);
}

// ---- settings ------------------------------------------------------------------

void Core::get_settings(const ClientInfo& client, SettingsCallback done) {
    settings_.request(client.id, admit(client, Arbiter::Needs::kAccessAndControl), std::nullopt,
                      std::move(done));
}

void Core::set_settings(const ClientInfo& client, SettingsChange change, SettingsCallback done) {
    settings_.request(client.id, admit(client, Arbiter::Needs::kAccessAndControl), change,
                      std::move(done));
}

}  // namespace gport::daemon
