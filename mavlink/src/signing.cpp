#include "gport/mavlink/signing.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "gport/base/hex.hpp"

namespace gport::mavlink {

namespace {

// The frame's expected size from its header: 0 when it is too short to say.
std::size_t signed_size_of(std::span<const std::uint8_t> frame) {
    if (frame.size() < kHeaderSizeV2 || frame[0] != kMagicV2) {
        return 0;
    }
    return kHeaderSizeV2 + frame[1] + kChecksumSize + kSignatureSize;
}

// now + SendClock::kMaxLead, saturated at 48 bits.
std::uint64_t lead_limit(std::uint64_t now) {
    return std::min(now, kMaxTimestamp - SendClock::kMaxLead) + SendClock::kMaxLead;
}

}  // namespace

void wipe(std::span<char> secret) {
    OPENSSL_cleanse(secret.data(), secret.size());
}

SecretKey::~SecretKey() {
    OPENSSL_cleanse(bytes_.data(), bytes_.size());
}

Result<SecretKey> parse_key_hex(std::string_view text) {
    const std::string allowed =
        "; allowed: exactly 64 hexadecimal digits (0-9, a-f), the 32-byte key";
    if (text.size() != 2 * kSecretKeySize) {
        return Error{std::to_string(text.size()) + " characters" + allowed};
    }
    std::array<std::uint8_t, kSecretKeySize> bytes{};
    for (std::size_t i = 0; i < text.size(); ++i) {
        const int v = base::hex_digit(text[i]);
        if (v < 0) {
            // Appended, not `"..." + std::to_string(...)`: 32-bit ARM's g++ 12
            // sees a false overlap in that (-Wrestrict, GCC bug 105329).
            std::string what = "character ";
            what.append(std::to_string(i + 1))
                .append(" is not a hexadecimal digit")
                .append(allowed);
            return Error{std::move(what)};
        }
        bytes[i / 2] = static_cast<std::uint8_t>(bytes[i / 2] << 4 | v);
    }
    SecretKey key(bytes);
    OPENSSL_cleanse(bytes.data(), bytes.size());
    return key;
}

std::uint64_t signing_timestamp(std::chrono::system_clock::time_point time) {
    using namespace std::chrono;
    const auto since_unix = duration_cast<microseconds>(time.time_since_epoch()).count();
    const std::int64_t epoch_us = kSigningEpochUnixSeconds * 1'000'000;
    if (since_unix <= epoch_us) {
        return 0;
    }
    return std::min<std::uint64_t>(static_cast<std::uint64_t>(since_unix - epoch_us) / 10,
                                   kMaxTimestamp);
}

SendClock::SendClock(std::uint64_t floor, std::uint64_t now)
    : last_(std::min(std::max(floor, now), kMaxTimestamp)) {}

std::uint64_t SendClock::next(std::uint64_t now) {
    last_ = std::min(std::max(last_ + 1, now), kMaxTimestamp);
    return last_;
}

SendClock::Observed SendClock::observe(std::uint64_t accepted, std::uint64_t now) {
    const std::uint64_t limit = lead_limit(now);
    const std::uint64_t before = last_;
    last_ = std::max(last_, std::min(accepted, limit));
    return {last_ - before, accepted > limit};
}

std::uint64_t SendClock::reference(std::uint64_t now) const {
    return std::max(now, std::min(last_, lead_limit(now)));
}

std::uint64_t trusted_floor(std::uint64_t stored, std::uint64_t now) {
    return std::min(stored, lead_limit(now));
}

std::optional<SignatureBlock> signature_block_of(std::span<const std::uint8_t> frame) {
    if (frame.size() < kHeaderSizeV2 || (frame[2] & kIncompatSigned) == 0 ||
        signed_size_of(frame) != frame.size()) {
        return std::nullopt;
    }
    const auto block = frame.last(kSignatureSize);
    SignatureBlock out;
    out.link_id = block[0];
    for (std::size_t i = 0; i < 6; ++i) {
        out.timestamp |= std::uint64_t{block[1 + i]} << (8 * i);
    }
    std::copy_n(block.begin() + 7, kSignatureValueSize, out.value.begin());
    return out;
}

SignatureValue compute_signature(const SecretKey& key, std::span<const std::uint8_t> covered) {
    // The key and the covered bytes in one buffer, hashed in one call; the
    // buffer is wiped afterwards (it holds the key).
    std::array<std::uint8_t, kSecretKeySize + kMaxFrameSize> input{};
    if (covered.size() > kMaxFrameSize) {
        throw std::invalid_argument("MAVLink frame of " + std::to_string(covered.size()) +
                                    " bytes to sign; at most 280");
    }
    std::copy(key.bytes().begin(), key.bytes().end(), input.begin());
    std::copy(covered.begin(), covered.end(), input.begin() + kSecretKeySize);
    std::array<std::uint8_t, EVP_MAX_MD_SIZE> digest{};
    unsigned int digest_size = 0;
    const int ok = EVP_Digest(input.data(), kSecretKeySize + covered.size(), digest.data(),
                              &digest_size, EVP_sha256(), nullptr);
    OPENSSL_cleanse(input.data(), input.size());
    if (ok != 1 || digest_size < kSignatureValueSize) {
        throw std::runtime_error("OpenSSL EVP_Digest(SHA-256) failed");
    }
    SignatureValue value{};
    std::copy_n(digest.begin(), kSignatureValueSize, value.begin());
    return value;
}

bool signature_matches(const SecretKey& key, std::span<const std::uint8_t> frame) {
    const auto block = signature_block_of(frame);
    return block && signature_matches(key, frame, *block);
}

bool signature_matches(const SecretKey& key, std::span<const std::uint8_t> frame,
                       const SignatureBlock& block) {
    const SignatureValue expected =
        compute_signature(key, frame.first(frame.size() - kSignatureValueSize));
    return CRYPTO_memcmp(expected.data(), block.value.data(), kSignatureValueSize) == 0;
}

void sign(Frame& frame, const SecretKey& key, std::uint8_t link_id, std::uint64_t timestamp) {
    const auto block = frame.signature_block();
    if (block.empty()) {
        throw std::invalid_argument("sign(): the frame was built unsigned");
    }
    if (timestamp > kMaxTimestamp) {
        throw std::invalid_argument("sign(): timestamp " + std::to_string(timestamp) +
                                    " does not fit 48 bits");
    }
    block[0] = link_id;
    for (std::size_t i = 0; i < 6; ++i) {
        block[1 + i] = static_cast<std::uint8_t>((timestamp >> (8 * i)) & 0xFFU);
    }
    const auto bytes = frame.bytes();
    const SignatureValue value = compute_signature(key, bytes.first(bytes.size() - 6));
    std::copy(value.begin(), value.end(), block.begin() + 7);
}

}  // namespace gport::mavlink
