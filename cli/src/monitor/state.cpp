#include "state.hpp"

#include <fmt/format.h>

#include <type_traits>
#include <variant>

#include "gport/cli/printable.hpp"
#include "text.hpp"

namespace gport::cli::monitor {
namespace {

using std::chrono::duration_cast;
using std::chrono::milliseconds;

std::int64_t ms_between(SteadyTime from, SteadyTime to) {
    return std::max<std::int64_t>(duration_cast<milliseconds>(to - from).count(), 0);
}

Severity link_severity(const std::string& state) {
    if (state == "up") {
        return Severity::kGood;
    }
    return state == "stale" ? Severity::kWarn : Severity::kBad;
}

// "speed started by pid 812 (client 4): yaw +30.0 °/s for 2.0 s"
std::string describe(const client::MotionEvent& event, const std::string& owner) {
    std::string text = fmt::format("{} {}", event.mode, event.change);
    if (event.change != "ended") {
        text += " by " + owner;
    }
    if (event.speed && event.change != "ended") {
        text += ": " + axes_text(*event.speed, "°/s");
    } else if (event.target && event.change != "ended") {
        text += ": to " + axes_text(*event.target, "°");
    }
    if (event.duration_ms && event.change != "ended") {
        text += " for " + duration_text(*event.duration_ms);
    }
    if (event.reason) {
        text += (event.change == "ended" ? ": " : ", ") + *event.reason;
    }
    return text;
}

// Every text of the model that gportd, a client or the system supplied, made
// printable (issue 30): both renderers draw only what the model holds.
void make_printable(MonitorModel& m) {
    for (auto* text : {&m.socket, &m.connection_error, &m.daemon_version, &m.link_state,
                       &m.link_reason, &m.device, &m.controller, &m.recording}) {
        *text = printable(*text);
    }
    if (m.motion) {
        m.motion->mode = printable(m.motion->mode);
        m.motion->owner = printable(m.motion->owner);
    }
    if (m.last_end) {
        m.last_end->mode = printable(m.last_end->mode);
        m.last_end->reason = printable(m.last_end->reason);
    }
    for (auto& event : m.events) {
        event.text = printable(event.text);
    }
}

}  // namespace

MonitorState::MonitorState(std::string socket, bool control_requested) {
    base_.socket = std::move(socket);
    base_.control_requested = control_requested;
}

void MonitorState::on_connected(const Now& now) {
    base_.connected = true;
    base_.connection_error.clear();
    base_.stale_since.clear();
    note(fmt::format("connected to gportd at {}", base_.socket), Severity::kGood, now);
}

void MonitorState::on_disconnected(const std::string& why, const Now& now) {
    if (base_.connected || base_.stale_since.empty()) {
        base_.stale_since = now.clock;
    }
    if (base_.connected) {
        note("lost the connection to gportd: " + why, Severity::kBad, now);
    }
    base_.connected = false;
    base_.connection_error = why;
    base_.link_state = "unknown";
    base_.holds_control = false;
    motion_.reset();
    status_age_.reset();
    last_sample_at_.reset();
    frames_seen_.reset();
    base_.frame_rate_hz.reset();
}

void MonitorState::on_status(const client::Status& status, const Now& now) {
    self_id_ = status.self.id;
    base_.daemon_version = status.daemon_version;
    uptime_ = std::pair(now.steady, status.uptime_ms);
    set_link(status.link.state, status.link.reason, now);
    base_.device = status.device;
    base_.device_open = status.device_open;
    if (status.attitude_age_ms) {
        status_age_ = std::pair(now.steady, *status.attitude_age_ms);
    } else {
        status_age_.reset();
    }
    const auto frames = status.counters.attitude_frames;
    if (frames_seen_ && now.steady > frames_seen_->first && frames >= frames_seen_->second) {
        const double seconds =
            std::chrono::duration<double>(now.steady - frames_seen_->first).count();
        base_.frame_rate_hz = static_cast<double>(frames - frames_seen_->second) / seconds;
    }
    frames_seen_ = std::pair(now.steady, frames);
    base_.counters = status.counters;
    base_.clients = status.clients;
    base_.dropped_total = status.dropped_notifications;
    base_.dropped_self = status.self_dropped;
    base_.recording = status.recording;
    base_.controller = status.controller ? peer_text(status.controller, self_id_) : "free";
    base_.holds_control = status.controller && status.controller->id == self_id_;
    if (status.motion) {
        motion_ = TimedMotion{view_of(*status.motion), now.steady};
    } else {
        motion_.reset();
    }
}

void MonitorState::on_notification(const client::Notification& notification, const Now& now) {
    std::visit(
        [&](const auto& n) {
            using T = std::decay_t<decltype(n)>;
            if constexpr (std::is_same_v<T, client::AttitudeSample>) {
                on_attitude(n, now);
            } else if constexpr (std::is_same_v<T, client::LinkEvent>) {
                on_link(n, now);
            } else {
                on_motion(n, now);
            }
        },
        notification);
}

void MonitorState::on_control(bool holds, const Now& now) {
    if (holds != base_.holds_control) {
        note(holds ? "control acquired" : "control released", Severity::kInfo, now);
    }
    base_.holds_control = holds;
    if (holds) {
        base_.controller = "you";
    }
}

void MonitorState::note(std::string text, Severity severity, const Now& now) {
    events_.push_back(EventLine{now.clock, std::move(text), severity});
    ++base_.events_total;
    while (events_.size() > kMaxEvents) {
        events_.pop_front();
    }
}

void MonitorState::on_attitude(const client::AttitudeSample& sample, const Now& now) {
    base_.attitude = sample;
    last_sample_at_ = now.steady;
    base_.dropped_self = std::max(base_.dropped_self, sample.dropped);
}

void MonitorState::on_link(const client::LinkEvent& event, const Now& now) {
    set_link(event.state, event.reason, now);
}

void MonitorState::set_link(const std::string& state, const std::string& reason, const Now& now) {
    if (state != base_.link_state) {
        note(fmt::format("link {}{}", state, reason.empty() ? "" : ": " + reason),
             link_severity(state), now);
    }
    base_.link_state = state;
    base_.link_reason = reason;
}

void MonitorState::on_motion(const client::MotionEvent& event, const Now& now) {
    const std::string owner = peer_text(event.owner, self_id_);
    note(describe(event, owner), event.change == "ended" ? Severity::kInfo : Severity::kGood, now);
    if (event.change == "ended") {
        base_.last_end = MotionEnd{event.mode, event.reason.value_or("?"), now.clock};
        motion_.reset();
        return;
    }
    MotionView view{.mode = event.mode, .owner = owner};
    view.speed = event.speed;
    view.target = event.target;
    view.time_left_ms = event.duration_ms;
    view.elapsed_ms = 0;
    if (event.change == "updated" && motion_) {  // the same motion: keep its clock
        view.elapsed_ms =
            motion_->view.elapsed_ms.value_or(0) + ms_between(motion_->seen, now.steady);
    }
    motion_ = TimedMotion{view, now.steady};
}

MotionView MonitorState::view_of(const client::Motion& motion) const {
    return MotionView{.mode = motion.mode,
                      .owner = peer_text(motion.owner, self_id_),
                      .speed = motion.speed,
                      .target = motion.target,
                      .time_left_ms = motion.time_left_ms,
                      .elapsed_ms = motion.elapsed_ms};
}

MonitorModel MonitorState::model(const Now& now) const {
    MonitorModel m = base_;
    m.clock = now.clock;
    if (uptime_) {
        m.uptime_ms = uptime_->second + ms_between(uptime_->first, now.steady);
    }
    if (last_sample_at_) {
        m.attitude_age_ms = ms_between(*last_sample_at_, now.steady);
    } else if (status_age_) {
        m.attitude_age_ms = status_age_->second + ms_between(status_age_->first, now.steady);
    }
    if (motion_) {
        MotionView view = motion_->view;
        const auto passed = ms_between(motion_->seen, now.steady);
        if (view.time_left_ms) {
            view.time_left_ms = std::max<std::int64_t>(*view.time_left_ms - passed, 0);
        }
        if (view.elapsed_ms) {
            view.elapsed_ms = *view.elapsed_ms + passed;
        }
        m.motion = view;
    }
    m.events.assign(events_.begin(), events_.end());
    make_printable(m);
    return m;
}

}  // namespace gport::cli::monitor
