// MAVLink 2 message signing (mavlink.io, guide/message_signing): the secret
// key, the signing timestamp, and signing and reading the 13-byte block.
//
// A signed frame has incompat flag 0x01 (covered by the checksum) and, after
// the checksum:
//
//   offset  size  field
//   0       1     link id: the sender's link (part of its stream's identity)
//   1       6     timestamp, little-endian: 10 µs units since 2015-01-01 UTC
//   7       6     signature: the first 48 bits of
//                 SHA-256(secret key + header + payload + checksum + link id + timestamp)
//
// i.e. SHA-256 over the 32-byte key followed by the whole frame except its
// last 6 bytes. SHA-256 is OpenSSL's libcrypto (EVP); this library, unlike
// the codec, links it. Pure otherwise: no I/O, no clock (callers pass
// timestamps), no globals.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "gport/mavlink/frame.hpp"
#include "gport/mavlink/result.hpp"

namespace gport::mavlink {

// ---- the key ---------------------------------------------------------------

inline constexpr std::size_t kSecretKeySize = 32;

// The 32-byte shared secret. Its bytes are wiped (OPENSSL_cleanse) when it
// is destroyed.
class SecretKey {
  public:
    SecretKey() = default;
    explicit SecretKey(const std::array<std::uint8_t, kSecretKeySize>& bytes) : bytes_(bytes) {}
    SecretKey(const SecretKey&) = default;
    SecretKey& operator=(const SecretKey&) = default;
    ~SecretKey();
    std::span<const std::uint8_t, kSecretKeySize> bytes() const { return bytes_; }

  private:
    std::array<std::uint8_t, kSecretKeySize> bytes_{};
};

// The key written as 64 hexadecimal digits (either case), nothing else (the
// caller trims surrounding whitespace). The error says what is wrong (the
// length, or the first character that is not a hex digit, by position)
// and what is allowed, never the key.
Result<SecretKey> parse_key_hex(std::string_view text);

// Overwrites secret bytes (OPENSSL_cleanse: not optimised away), e.g. a key
// file's text once parsed.
void wipe(std::span<char> secret);

// ---- timestamps -------------------------------------------------------------

inline constexpr std::uint64_t kMaxTimestamp = (std::uint64_t{1} << 48) - 1;
// 10 µs units per second, and the one-minute window of the acceptance rules.
inline constexpr std::uint64_t kTimestampsPerSecond = 100'000;
inline constexpr std::uint64_t kOneMinute = 60 * kTimestampsPerSecond;
// 2015-01-01T00:00:00Z in Unix seconds.
inline constexpr std::int64_t kSigningEpochUnixSeconds = 1'420'070'400;

// The signing timestamp of a wall-clock time: 0 before 2015, saturated at
// 48 bits.
std::uint64_t signing_timestamp(std::chrono::system_clock::time_point time);

// The timestamp of a node's outgoing frames: each at least one more than the
// previous one, kept up with the clock (so that receivers that restart, and
// apply the one-minute rule to our new stream, accept it), raised to a
// greater timestamp of a frame the node obeys (the specification's rule;
// the caller decides which frames those are) but never above now +
// kMaxLead by it, and never below `floor`, the persisted value every
// earlier one stayed under (the start is max(clock, floor); trusted_floor()
// bounds a stored value). Saturates at 48 bits: then every frame carries the
// same timestamp and receivers take only the first (saturated() says so).
//
// Why the lead is bounded (issue 30): one accepted frame from a key holder
// with a wrong clock, or a forged one stamped hours ahead, would otherwise
// drag our clock there (and it is persisted): peers whose clocks are right
// would then start new streams more than a minute behind ours and be
// refused as "too old", and our own frames would pull every peer that
// follows our timestamp ahead too. kMaxLead is half the one-minute window:
// a peer whose clock is right stays 30 s inside it whatever a key holder
// sent us.
class SendClock {
  public:
    // How far ahead of our wall clock ours may be pulled by a peer, and how
    // far ahead of it the reference for incoming new streams may be: 30 s.
    static constexpr std::uint64_t kMaxLead = 30 * kTimestampsPerSecond;

    SendClock(std::uint64_t floor, std::uint64_t now);
    // The timestamp for the next frame: max(previous + 1, now).
    std::uint64_t next(std::uint64_t now);

    // What observe() did: how far it raised ours, and whether the peer's
    // timestamp was beyond now + kMaxLead (ours stops there).
    struct Observed {
        std::uint64_t raised = 0;
        bool capped = false;
    };
    // The timestamp of a correctly signed frame from a system we obey: ours
    // if greater, but not above now + kMaxLead.
    Observed observe(std::uint64_t accepted, std::uint64_t now);

    // Our timestamp as the reference of the incoming one-minute rule
    // (Verifier::check's `local`): ours, but not behind the wall clock nor
    // more than kMaxLead ahead of it, so that however far a stored value or
    // a peer put ours, a sender whose clock is right is never "too old".
    std::uint64_t reference(std::uint64_t now) const;

    // The greatest timestamp issued or observed so far.
    std::uint64_t current() const { return last_; }
    // At 2^48 - 1: every frame now repeats the same timestamp.
    bool saturated() const { return last_ >= kMaxTimestamp; }

  private:
    std::uint64_t last_;
};

// The floor a stored timestamp gives at start: the stored value, but at
// most now + SendClock::kMaxLead. A node that follows these rules with a
// clock that does not go back never sent anything above that (its frames
// stay within kMaxLead of its clock), so the peers that saw its frames
// still see newer ones; anything higher (a file planted at 2^48 - 1, a
// value from an older version that followed a peer a day ahead, or a
// reservation beyond what was sent) is not trusted beyond it.
std::uint64_t trusted_floor(std::uint64_t stored, std::uint64_t now);

// ---- signatures --------------------------------------------------------------

inline constexpr std::size_t kSignatureValueSize = 6;
using SignatureValue = std::array<std::uint8_t, kSignatureValueSize>;

struct SignatureBlock {
    std::uint8_t link_id = 0;
    std::uint64_t timestamp = 0;
    SignatureValue value{};
};

// The signature block of a whole frame (FrameView::bytes); nullopt when the
// frame is not flagged signed, or is shorter or longer than its header,
// payload length, checksum and 13 signature bytes add up to.
std::optional<SignatureBlock> signature_block_of(std::span<const std::uint8_t> frame);

// The first 48 bits of SHA-256(key + covered), where `covered` is the frame
// without the signature value (its last 6 bytes).
SignatureValue compute_signature(const SecretKey& key, std::span<const std::uint8_t> covered);

// True when a whole signed frame's signature is the one `key` makes
// (compared in constant time); false for an unsigned or malformed frame.
bool signature_matches(const SecretKey& key, std::span<const std::uint8_t> frame);
// The same with the frame's signature block already read
// (signature_block_of(frame)), so that it is not read twice.
bool signature_matches(const SecretKey& key, std::span<const std::uint8_t> frame,
                       const SignatureBlock& block);

// Fills in the signature block of a frame built signed (Frame::make with
// signed_frame, encode(..., true)). Throws std::invalid_argument for an
// unsigned frame or a timestamp over 48 bits (programming errors).
void sign(Frame& frame, const SecretKey& key, std::uint8_t link_id, std::uint64_t timestamp);

}  // namespace gport::mavlink
