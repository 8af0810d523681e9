// The session's transition table (session_state.hpp; the same table is in
// docs/architecture.md, "A session's state").
#include "gport/ipc/session_state.hpp"

#include <fmt/format.h>

namespace gport::ipc {
namespace {

using State = SessionState;
using Next = std::optional<SessionState>;

// Input: `from` -> `to`, when the life allows it.
Next input(State s, Input from, Input to, bool life_allows) {
    if (s.input != from || !life_allows) {
        return std::nullopt;
    }
    s.input = to;
    return s;
}

// Output: `from` -> `to`, when the life allows it.
Next output(State s, Output from, Output to, bool life_allows) {
    if (s.output != from || !life_allows) {
        return std::nullopt;
    }
    s.output = to;
    return s;
}

}  // namespace

Next transition(State s, SessionEvent event) {
    const bool open = s.life == Life::kOpen;
    const bool not_closed = s.life != Life::kClosed;
    constexpr bool kAnyLife = true;  // completions of waits started earlier
    switch (event) {
        case SessionEvent::kReadStarted:
            return input(s, Input::kIdle, Input::kReading, open);
        case SessionEvent::kReadDone:
            return input(s, Input::kReading, Input::kIdle, kAnyLife);
        case SessionEvent::kYielded:
            return input(s, Input::kIdle, Input::kPosted, open);
        case SessionEvent::kUnpaused:
            return input(s, Input::kPaused, Input::kPosted, not_closed);
        case SessionEvent::kResumed:
            return input(s, Input::kPosted, Input::kIdle, kAnyLife);
        case SessionEvent::kBacklogged:
            return input(s, Input::kIdle, Input::kPaused, open);
        case SessionEvent::kThrottled:
            return input(s, Input::kIdle, Input::kThrottled, open);
        case SessionEvent::kThrottleEnded:
            return input(s, Input::kThrottled, Input::kIdle, kAnyLife);
        case SessionEvent::kHungUp: {
            auto next = input(s, Input::kIdle, Input::kHungUp, open);
            if (next) {
                next->life = Life::kClosing;
            }
            return next;
        }
        case SessionEvent::kRefused:
            if (!open) {
                return std::nullopt;
            }
            s.life = Life::kClosing;  // a wait in progress completes on its own
            return s;
        case SessionEvent::kClosed:
            if (!not_closed) {
                return std::nullopt;
            }
            s.life = Life::kClosed;
            return s;
        case SessionEvent::kWriteStarted:
            return output(s, Output::kIdle, Output::kWriting, not_closed);
        case SessionEvent::kWritten:
            return output(s, Output::kWriting, Output::kIdle, kAnyLife);
        case SessionEvent::kWaitWritable:
            return output(s, Output::kIdle, Output::kWaiting, not_closed);
        case SessionEvent::kWritable:
            return output(s, Output::kWaiting, Output::kIdle, kAnyLife);
    }
    return std::nullopt;
}

std::string_view to_string(Life life) {
    switch (life) {
        case Life::kOpen:
            return "open";
        case Life::kClosing:
            return "closing";
        case Life::kClosed:
            return "closed";
    }
    return "?";
}

std::string_view to_string(Input input) {
    switch (input) {
        case Input::kIdle:
            return "idle";
        case Input::kReading:
            return "reading";
        case Input::kPosted:
            return "posted";
        case Input::kPaused:
            return "paused";
        case Input::kThrottled:
            return "throttled";
        case Input::kHungUp:
            return "hung_up";
    }
    return "?";
}

std::string_view to_string(Output output) {
    switch (output) {
        case Output::kIdle:
            return "idle";
        case Output::kWriting:
            return "writing";
        case Output::kWaiting:
            return "waiting";
    }
    return "?";
}

std::string_view to_string(SessionEvent event) {
    switch (event) {
        case SessionEvent::kReadStarted:
            return "read_started";
        case SessionEvent::kReadDone:
            return "read_done";
        case SessionEvent::kYielded:
            return "yielded";
        case SessionEvent::kUnpaused:
            return "unpaused";
        case SessionEvent::kResumed:
            return "resumed";
        case SessionEvent::kBacklogged:
            return "backlogged";
        case SessionEvent::kThrottled:
            return "throttled";
        case SessionEvent::kThrottleEnded:
            return "throttle_ended";
        case SessionEvent::kHungUp:
            return "hung_up";
        case SessionEvent::kRefused:
            return "refused";
        case SessionEvent::kClosed:
            return "closed";
        case SessionEvent::kWriteStarted:
            return "write_started";
        case SessionEvent::kWritten:
            return "written";
        case SessionEvent::kWaitWritable:
            return "wait_writable";
        case SessionEvent::kWritable:
            return "writable";
    }
    return "?";
}

std::string to_string(const SessionState& state) {
    return fmt::format("{}/{}/{}", to_string(state.life), to_string(state.input),
                       to_string(state.output));
}

}  // namespace gport::ipc
