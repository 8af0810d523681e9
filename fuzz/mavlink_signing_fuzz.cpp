// libFuzzer target for MAVLink 2 signing (mavlink/src/signing.cpp,
// verifier.cpp): the bytes an attacker controls on a signed link.
//
// The input is fed to the decoder; every delivered frame, and the raw
// input itself, goes through a Verifier with a fixed key. Whatever the
// bytes: nothing crashes, an unsigned frame is kUnsigned, an accepted
// frame's signature matches the key (so only the key's holder gets
// anything accepted), and the stream table never outgrows its bound.
// Those checks guard the refusals; "accepted" and the stream table cannot
// be reached from an attacker's bytes (no signature without the key). So
// the input is also read as a key holder's traffic (stream_table): 10-byte
// records, each a frame signed with the key for a (system, component,
// link) stream and a timestamp, at a local time that only goes forward.
// Whatever the sequence: a key holder's frame is never refused as
// unsigned or badly signed, no (stream, timestamp) pair is accepted twice
// (replay protection, eviction included), and the table stays in bounds.
// Then the input is signed as a payload (its first bytes pick the link id
// and timestamp): the decoder must deliver it as one signed frame that
// verifies, that a fresh Verifier accepts, and whose replay it refuses.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <span>
#include <tuple>

#include "gport/mavlink/decoder.hpp"
#include "gport/mavlink/messages.hpp"
#include "gport/mavlink/verifier.hpp"

namespace gm = gport::mavlink;

namespace {

void require(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "mavlink_signing_fuzz invariant broken: %s\n", what);
        std::abort();
    }
}

gm::SecretKey fuzz_key() {
    std::array<std::uint8_t, gm::kSecretKeySize> bytes{};
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        bytes[i] = static_cast<std::uint8_t>(0xA5 ^ (i * 7));
    }
    return gm::SecretKey(bytes);
}

void judge(gm::Verifier& verifier, const gm::SecretKey& key, std::span<const std::uint8_t> frame,
           std::uint64_t local) {
    const gm::Verdict verdict = verifier.check(frame, local);
    const bool flagged = frame.size() >= gm::kHeaderSizeV2 && (frame[2] & gm::kIncompatSigned) != 0;
    if (!flagged) {
        require(verdict.check == gm::SignatureCheck::kUnsigned, "unflagged frame not kUnsigned");
    }
    if (verdict.check == gm::SignatureCheck::kAccepted) {
        require(gm::signature_matches(key, frame), "accepted without the key's signature");
        require(gm::signature_block_of(frame).has_value(), "accepted without a whole block");
    }
    require(verifier.streams() <= verifier.max_streams(), "stream table over its bound");
}

std::uint64_t read48(std::span<const std::uint8_t> in, std::size_t at) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < 6 && at + i < in.size(); ++i) {
        v |= std::uint64_t{in[at + i]} << (8 * i);
    }
    return v;
}

void sign_round_trip(std::span<const std::uint8_t> in, const gm::SecretKey& key) {
    const std::uint8_t link = in.empty() ? 0 : in[0];
    const std::uint64_t timestamp = read48(in, 1);
    const auto payload = in.subspan(0, std::min<std::size_t>(in.size(), 9));  // HEARTBEAT's size
    gm::Frame frame = gm::Frame::make({7, 1, 1}, gm::Heartbeat::kId, gm::Heartbeat::kCrcExtra,
                                      payload, /*signed_frame=*/true);
    gm::sign(frame, key, link, timestamp);
    gm::Decoder decoder;
    int frames = 0;
    gm::Verifier verifier(key, 4);
    decoder.feed(frame.bytes(), [&](const gm::FrameView& view) {
        ++frames;
        require(view.is_signed, "a signed frame delivered unsigned");
        require(std::ranges::equal(view.bytes, frame.bytes()), "delivered bytes differ");
        require(verifier.check(view.bytes, timestamp).check == gm::SignatureCheck::kAccepted,
                "our own signed frame refused");
        require(verifier.check(view.bytes, timestamp).check == gm::SignatureCheck::kReplayed,
                "a replay accepted");
    });
    require(frames == 1, "a signed frame not delivered once");
}

void stream_table(std::span<const std::uint8_t> in, const gm::SecretKey& key) {
    constexpr std::size_t kRecord = 10;
    gm::Verifier verifier(key, 4);  // small: fills up and evicts
    std::set<std::tuple<std::uint8_t, std::uint8_t, std::uint8_t, std::uint64_t>> accepted;
    std::uint64_t local = 0;
    const std::array<std::uint8_t, 9> payload{};
    for (std::size_t at = 0; at + kRecord <= in.size(); at += kRecord) {
        const std::uint8_t sysid = in[at] % 8;  // few streams: they repeat
        const std::uint8_t compid = in[at + 1] % 2;
        const std::uint8_t link = in[at + 2] % 2;
        const std::uint64_t timestamp = read48(in, at + 3) % (8 * gm::kOneMinute);
        local += std::uint64_t{in[at + 9]} * (gm::kOneMinute / 64);  // never backwards
        gm::Frame frame = gm::Frame::make({0, sysid, compid}, gm::Heartbeat::kId,
                                          gm::Heartbeat::kCrcExtra, payload, true);
        gm::sign(frame, key, link, timestamp);
        const gm::Verdict verdict = verifier.check(frame.bytes(), local);
        require(verdict.check != gm::SignatureCheck::kUnsigned &&
                    verdict.check != gm::SignatureCheck::kBadSignature,
                "a key holder's frame refused as unsigned or badly signed");
        require(verdict.timestamp == timestamp, "the verdict's timestamp is not the frame's");
        if (verdict.check == gm::SignatureCheck::kAccepted) {
            require(accepted.emplace(sysid, compid, link, timestamp).second,
                    "a (stream, timestamp) accepted twice: a replay got through");
        }
        require(verifier.streams() <= verifier.max_streams(), "stream table over its bound");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> in(data, size);
    static const gm::SecretKey key = fuzz_key();
    gm::Verifier verifier(key, 8);
    const std::uint64_t local = read48(in, 0);
    gm::Decoder decoder;
    decoder.feed(in, [&](const gm::FrameView& view) { judge(verifier, key, view.bytes, local); });
    judge(verifier, key, in, local);
    sign_round_trip(in, key);
    stream_table(in, key);
    return 0;
}
