// A client session's state as three orthogonal parts, and the one function
// that says which event may happen in which state (docs/architecture.md,
// "A session's state"). Pure: no sockets, no timers, unit-tested on its own.
//
// - Life: whether the session takes requests and whether its socket is open.
// - Input: the one thing the request side waits for. At most one wait is
//   pending at a time (a read, a posted continuation, the client draining its
//   replies, or the throttle timer), so it is one value, not four flags.
// - Output: the one write in flight, if any.
//
// The parts are independent except where the table says otherwise: a wait
// started while the session was open still completes after it closes (an
// aborted read, a cancelled timer), so Input and Output have their own
// completion events, legal in every Life. Once the session is closing no
// new input wait starts (except the continuation that drains a paused
// client) while writes go on, since the replies owed are still written;
// once it is closed nothing new starts at all.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace gport::ipc {

enum class Life {
    kOpen,     // reads and handles requests
    kClosing,  // takes no more requests; closes once every reply owed is written
    kClosed,   // the socket is closed and the host was told; final
};

enum class Input {
    kIdle,       // nothing pending: not started yet, handling lines now, or stopped
    kReading,    // one async read in flight
    kPosted,     // yielded after a turn's worth of lines; continues on a later turn
    kPaused,     // back-pressure: waits until the client has read its replies
    kThrottled,  // over the request rate: waits for the throttle timer
    kHungUp,     // the client sent EOF and the deadman ran for it; final
};

enum class Output {
    kIdle,     // writes are tried at once, without waiting
    kWriting,  // the rest of a batch is being written asynchronously
    kWaiting,  // a reply with descriptors waits for the socket to drain
};

enum class SessionEvent {
    kReadStarted,    // read(): an async read is started
    kReadDone,       // on_read(): it completed (data, EOF, error or aborted)
    kYielded,        // process_input(): a turn's worth handled; the rest is posted
    kUnpaused,       // drained(): a paused client read its replies; input is posted
    kResumed,        // the posted continuation runs
    kBacklogged,     // process_input(): too many replies unread; handling pauses
    kThrottled,      // throttle(): out of request tokens; the throttle timer runs
    kThrottleEnded,  // the throttle timer fired or was cancelled
    kHungUp,         // hang_up(): EOF; the deadman runs, replies owed are still written
    kRefused,        // close_after_reply(): a last error is queued, then it closes
    kClosed,         // close()
    kWriteStarted,   // write_rest(): an async write of the rest of a batch
    kWritten,        // on_written(): it completed
    kWaitWritable,   // wait_writable(): a descriptor reply waits for the socket
    kWritable,       // the wait completed
};

struct SessionState {
    Life life = Life::kOpen;
    Input input = Input::kIdle;
    Output output = Output::kIdle;

    friend bool operator==(const SessionState&, const SessionState&) = default;
};

// The state after `event`, or nothing when the event is illegal in `from`
// (a bug in the session: the caller logs it and leaves the state as it was).
std::optional<SessionState> transition(SessionState from, SessionEvent event);

std::string_view to_string(Life life);
std::string_view to_string(Input input);
std::string_view to_string(Output output);
std::string_view to_string(SessionEvent event);
// "open/reading/idle": life, input, output.
std::string to_string(const SessionState& state);

}  // namespace gport::ipc
