// gport-mavlink's MAVLink 2 signing at run time (docs/mavlink.md,
// "Security"): every incoming frame through the Verifier before anything
// else sees it, every outgoing frame signed, and the outgoing timestamp
// kept monotonic across restarts by the timestamp file.
//
// Persistence: the file always holds a value at or above every timestamp
// sent (while this machine's clock does not go back: see below; the reservation in memory is
// updated only once it is on disk; a failed write is retried once a second, logged, and signing
// goes on). The state directory is locked for the session: a second process sharing it is refused
// at start. At start the clock starts at max(now, stored), the stored value trusted up to
// SendClock::kMaxLead (30 s) ahead of the clock only (trusted_floor(): a planted 2^48 - 1 is not
// taken), and that exact value is written back (checking that the file can be written without
// advancing it; a failure stops the start); an error says when the stored
// value was not trusted (more than a reservation above the start). The
// first frame actually sent, and then
// every one within 10 s of the reservation, writes a reservation 30 s
// ahead (about every 20 s while the clock drives it). Every exit that
// unwinds (a clean one, or an exception caught in main(): exit 71) writes
// the exact current value, through close() or the destructor, so starts
// that fail, or end, before sending do not move the value; only a crash
// (SIGKILL, SIGSEGV) after sending leaves a reservation, at most 30 s ahead
// of the last timestamp sent.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "gport/mavlink/bridge/signing_files.hpp"
#include "gport/mavlink/frame.hpp"
#include "gport/mavlink/verifier.hpp"
#include "logbook.hpp"

namespace gport::mavlink::bridge {

class SigningSession {
  public:
    static constexpr std::uint8_t kLinkId = 0;
    static constexpr std::uint64_t kReservation = 30 * kTimestampsPerSecond;
    static constexpr std::uint64_t kHeadroom = 10 * kTimestampsPerSecond;
    // A step of our clock by a peer's frame larger than this is logged.
    static constexpr std::uint64_t kNotedStep = 1 * kTimestampsPerSecond;

    // Reads the stored timestamp and writes the exact start value back; the
    // error names the file and the cause.
    static Result<std::unique_ptr<SigningSession>> open(SecretKey key, const std::string& state_dir,
                                                        Logbook& log);

    // True when the frame's signature is good (key, stream, age: the
    // Verifier, against SendClock::reference()); otherwise it is counted
    // and logged (per kind) and must be dropped. Does not move our clock.
    bool admit(const FrameView& frame);

    // An admitted frame that the trust rules allow (from the vehicle or a
    // ground station): our clock follows its timestamp, at most
    // SendClock::kMaxLead ahead of the wall clock (logged, limited, when it
    // moves by more than a second, or the frame is further ahead). Frames
    // of systems we ignore never move it (issue 30).
    void follow(const FrameView& frame);

    // Fills in a frame built signed.
    void sign(Frame& frame);

    // Writes the exact current timestamp (at exit; once).
    void close();
    // close(), unless done: an exception's exit path writes it too.
    ~SigningSession();
    SigningSession(const SigningSession&) = delete;
    SigningSession& operator=(const SigningSession&) = delete;

    // Frames per SignatureCheck (indexed by it; kAccepted counts the accepted).
    using Counts = std::array<std::uint64_t, kSignatureChecks.size()>;
    const Counts& counts() const { return counts_; }

  private:
    SigningSession(SecretKey key, TimestampFile file, std::uint64_t floor, std::uint64_t now,
                   Logbook& log);
    void explain_start(std::uint64_t stored, std::uint64_t now) const;
    std::optional<Error> reserve(std::uint64_t timestamp);
    void report(const FrameView& frame, const Verdict& verdict);
    std::string drop_text(const FrameView& frame, const Verdict& verdict) const;

    SecretKey key_;
    Verifier verifier_;
    TimestampFile file_;
    SendClock clock_;
    std::uint64_t reserved_ = 0;                        // the value in the file
    std::chrono::steady_clock::time_point retry_at_{};  // after a failed reservation
    bool closed_ = false;
    Logbook& log_;
    Counts counts_{};
};

}  // namespace gport::mavlink::bridge
