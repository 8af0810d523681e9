// gport-mavlink's MAVLink 2 signing at run time (docs/mavlink.md,
// "Security"): every incoming frame through the Verifier before anything
// else sees it, every outgoing frame signed, and the outgoing timestamp
// kept monotonic across restarts by the timestamp file.
//
// Persistence: the file always holds a value at or above every timestamp
// sent. At start the clock starts at max(now, stored) and a reservation of
// 30 s ahead is written (a failure to write it stops the start); whenever
// the timestamp comes within 10 s of the reservation a new one is written
// (about every 20 s while the clock drives it); at a clean exit the exact
// last timestamp is written, so a restart does not jump ahead.
#pragma once

#include <array>
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

    // Reads the stored timestamp and writes the first reservation; the
    // error names the file and the cause.
    static Result<std::unique_ptr<SigningSession>> open(SecretKey key, const std::string& state_dir,
                                                        Logbook& log);

    // True when the frame may be acted on; otherwise it is counted and
    // logged (per kind) and must be dropped.
    bool admit(const FrameView& frame);

    // Fills in a frame built signed.
    void sign(Frame& frame);

    // Writes the exact last timestamp (at exit).
    void close();

    // Drops per SignatureCheck (index), kAccepted counting the accepted.
    const std::array<std::uint64_t, 6>& counts() const { return counts_; }
    std::uint64_t timestamp() const { return clock_.current(); }

  private:
    SigningSession(SecretKey key, TimestampFile file, std::uint64_t stored, std::uint64_t now,
                   Logbook& log);
    std::optional<Error> reserve(std::uint64_t timestamp);
    void report(SignatureCheck check, const FrameView& frame, const Verdict& verdict);

    SecretKey key_;
    Verifier verifier_;
    TimestampFile file_;
    SendClock clock_;
    std::uint64_t reserved_ = 0;
    Logbook& log_;
    std::array<std::uint64_t, 6> counts_{};
};

}  // namespace gport::mavlink::bridge
