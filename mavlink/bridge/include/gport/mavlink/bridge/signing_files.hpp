// gport-mavlink's two signing files (docs/mavlink.md, "Security"):
//
// The key file (--signing-key, config `signing_key`): the 32-byte secret as
// 64 hexadecimal digits, surrounding whitespace and newlines allowed,
// nothing else. It must be a regular file (a symbolic link to one is
// followed), owned by the effective user or root, that only its owner may
// read or write: another owner, any permission for the group or others
// refuses it, as does anything unreadable or malformed.
// Errors name the file, the problem and what is allowed; never the key.
//
// The timestamp file (DIR/signing-timestamp, DIR from --state-dir, config
// `state_dir` or $STATE_DIRECTORY): one decimal number, a signing
// timestamp that every timestamp sent so far stays at or under. Written
// whole to a temporary file of a unique name (mkstemp), synced and renamed
// over the old one, so a crash leaves the old value or the new one, never a
// torn one. The directory is locked (flock) by the one process using it:
// two processes sharing a state directory would publish each other's
// values (one's timestamps below the other's file); the second is refused.
// Before that it is checked (issue 30): owned by the effective user or
// root, and writable by neither group nor others, or another user could
// plant the file; the file is read with O_NOFOLLOW (a symbolic link in its
// place is refused) and must be a regular file. A planted value is bounded
// anyway: the session trusts a stored timestamp only up to 30 s ahead of
// the clock (trusted_floor(), signing.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "gport/mavlink/result.hpp"
#include "gport/mavlink/signing.hpp"

namespace gport::mavlink::bridge {

// The largest key file read: 64 digits and generous whitespace.
inline constexpr std::size_t kMaxKeyFileSize = 1024;

Result<SecretKey> load_signing_key(const std::string& path);

// The state directory's files (the signing timestamp, the image count:
// image_count.hpp) share its rules: the directory is ours or root's and
// writable by neither group nor others (the error says what to do), a file
// is opened with O_NOFOLLOW and must be a regular file, and is replaced
// whole (a temporary file, fsync, rename).
std::optional<Error> check_state_directory(const std::string& directory);
// The number stored at `path`: 0 when there is no file; an error naming
// the file, with `invalid` when it holds no decimal number up to `max`.
Result<std::uint64_t> load_state_number(const std::string& path, std::uint64_t max,
                                        std::string_view invalid);
std::optional<Error> save_state_number(const std::string& path, std::uint64_t value);

class TimestampFile {
  public:
    static constexpr const char* kFileName = "signing-timestamp";

    explicit TimestampFile(const std::string& directory);
    TimestampFile(TimestampFile&& other) noexcept;
    TimestampFile& operator=(TimestampFile&&) = delete;
    TimestampFile(const TimestampFile&) = delete;
    TimestampFile& operator=(const TimestampFile&) = delete;
    ~TimestampFile();  // releases the lock
    const std::string& path() const { return path_; }

    // Checks the directory (owner, mode: see above) and locks it for this
    // object's lifetime (an exclusive flock, not waited for); the error
    // names the directory and says what is wrong and what to do, or that
    // another process (another gport-mavlink) holds it.
    std::optional<Error> lock();

    // The stored timestamp; 0 when the file does not exist yet (first
    // start). An error names the file and the problem when it cannot be
    // read, is a symbolic link or no regular file, or does not hold one
    // number of at most 48 bits.
    Result<std::uint64_t> load() const;

    // Stores `timestamp`; the error names the file and the cause.
    std::optional<Error> save(std::uint64_t timestamp) const;

  private:
    std::string directory_;
    std::string path_;
    int lock_fd_ = -1;
};

}  // namespace gport::mavlink::bridge
