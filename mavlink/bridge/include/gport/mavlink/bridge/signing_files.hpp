// gport-mavlink's two signing files (docs/mavlink.md, "Security"):
//
// The key file (--signing-key, config `signing_key`): the 32-byte secret as
// 64 hexadecimal digits, surrounding whitespace and newlines allowed,
// nothing else. It must be a regular file (a symbolic link to one is
// followed) that only its owner may read or write: any permission for the
// group or others refuses it, as does anything unreadable or malformed.
// Errors name the file, the problem and what is allowed; never the key.
//
// The timestamp file (DIR/signing-timestamp, DIR from --state-dir, config
// `state_dir` or $STATE_DIRECTORY): one decimal number, a signing
// timestamp that every timestamp sent so far stays at or under. Written
// whole to a temporary file, synced and renamed over the old one, so a
// crash leaves the old value or the new one, never a torn one.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "gport/mavlink/result.hpp"
#include "gport/mavlink/signing.hpp"

namespace gport::mavlink::bridge {

// The largest key file read: 64 digits and generous whitespace.
inline constexpr std::size_t kMaxKeyFileSize = 1024;

Result<SecretKey> load_signing_key(const std::string& path);

class TimestampFile {
  public:
    static constexpr const char* kFileName = "signing-timestamp";

    explicit TimestampFile(const std::string& directory);
    const std::string& path() const { return path_; }

    // The stored timestamp; 0 when the file does not exist yet (first
    // start). An error names the file and the problem when it cannot be
    // read or does not hold one number of at most 48 bits.
    Result<std::uint64_t> load() const;

    // Stores `timestamp`; the error names the file and the cause.
    std::optional<Error> save(std::uint64_t timestamp) const;

  private:
    std::string path_;
};

}  // namespace gport::mavlink::bridge
