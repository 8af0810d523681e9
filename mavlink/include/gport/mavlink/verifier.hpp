// The acceptance rules for incoming frames on a signed link (mavlink.io,
// guide/message_signing, "Timestamp Handling" and "Accepting Signed
// Packets"), as a small pure state machine: the key, and a bounded table of
// streams, a stream being a (system id, component id, link id) tuple.
//
// A frame is accepted only when, in this order:
//   1. it is signed (no unsigned frame is accepted: no exceptions by
//      message or link, unlike RADIO_STATUS in some autopilots);
//   2. its signature block is whole and its signature is the key's;
//   3. on a known stream, its timestamp is greater than the stream's last
//      (equal is a replay too);
//   4. on a new stream, its timestamp is not more than one minute (6,000,000
//      units) behind our local timestamp, as the specification and the C
//      library apply it;
//   5. a new stream finds room in the table. When the table is full, a
//      stream whose last timestamp is more than a minute behind the local
//      one is forgotten to make room: any replay of it would be refused by
//      rule 4 anyway. Otherwise the new stream is refused (kStreamsFull).
// Only a frame that passes every rule updates its stream's timestamp:
// unsigned, wrongly signed or refused frames change nothing, so nobody
// without the key can touch the table.
//
// What the table does NOT cover: it lives in memory only. After a restart
// (of the program holding the Verifier) every stream is new again, so rule
// 4 alone judges them: a frame captured within the last minute before the
// restart (its timestamp not more than a minute behind the local one) is
// accepted once more if replayed after it, as with every MAVLink
// implementation that keeps no stream table across restarts (the C
// library included). The window is a minute of past traffic, and only
// until the real sender's next frame makes the stream known again (older
// captures are then replays). Persisting the table would close it at the
// cost of a write per accepted frame; gport-mavlink does not
// (docs/mavlink.md, "Signing").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "gport/mavlink/signing.hpp"

namespace gport::mavlink {

enum class SignatureCheck {
    kAccepted,
    kUnsigned,      // no signature (incompat flag 0x01 clear)
    kBadSignature,  // a signature that is not the key's, or a malformed block
    kReplayed,      // not newer than the last frame of its stream
    kTooOld,        // a new stream more than a minute behind the local timestamp
    kStreamsFull,   // a new stream and no room for it
};

// Every SignatureCheck, in order (kAccepted first): for counting per kind.
inline constexpr std::array<SignatureCheck, 6> kSignatureChecks{
    SignatureCheck::kAccepted, SignatureCheck::kUnsigned, SignatureCheck::kBadSignature,
    SignatureCheck::kReplayed, SignatureCheck::kTooOld,   SignatureCheck::kStreamsFull,
};
static_assert(
    [] {
        for (std::size_t i = 0; i < kSignatureChecks.size(); ++i) {
            if (static_cast<std::size_t>(kSignatureChecks[i]) != i) {
                return false;
            }
        }
        return true;
    }(),
    "kSignatureChecks lists SignatureCheck in order: counts are indexed by it");

// "unsigned", "bad signature", "replayed", "too old", "stream table full"
// ("accepted" for kAccepted): the kinds the bridge counts and logs.
std::string_view to_string(SignatureCheck check);

struct StreamKey {
    std::uint8_t sysid = 0;
    std::uint8_t compid = 0;
    std::uint8_t link_id = 0;
    friend bool operator==(const StreamKey&, const StreamKey&) = default;
};

struct Verdict {
    SignatureCheck check = SignatureCheck::kUnsigned;
    std::uint64_t timestamp = 0;  // the frame's, when its signature block was read
};

class Verifier {
  public:
    static constexpr std::size_t kDefaultMaxStreams = 32;

    explicit Verifier(SecretKey key, std::size_t max_streams = kDefaultMaxStreams);

    // Judges a whole frame (FrameView::bytes) against `local`, our current
    // timestamp (SendClock::current()). An accepted frame's timestamp
    // becomes its stream's last; the caller passes it to SendClock::observe.
    Verdict check(std::span<const std::uint8_t> frame, std::uint64_t local);

    std::size_t streams() const { return streams_.size(); }
    std::size_t max_streams() const { return max_streams_; }

  private:
    struct Stream {
        StreamKey key;
        std::uint64_t last = 0;
    };
    Verdict admit_new(const StreamKey& key, std::uint64_t timestamp, std::uint64_t local);

    SecretKey key_;
    std::size_t max_streams_;
    std::vector<Stream> streams_;  // at most max_streams_, reserved up front
};

}  // namespace gport::mavlink
