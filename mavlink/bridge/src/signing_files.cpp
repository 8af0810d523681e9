#include "gport/mavlink/bridge/signing_files.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <string_view>
#include <utility>

namespace gport::mavlink::bridge {

namespace {

std::string errno_text(int error) {
    return std::strerror(error);
}

// Closes a descriptor on every path.
class Fd {
  public:
    explicit Fd(int fd) : fd_(fd) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() {
        if (fd_ >= 0) {
            ::close(fd_);
        }
    }
    int get() const { return fd_; }

  private:
    int fd_;
};

// Which of group and others may do what: "group-readable, world-writable".
std::string loose_permissions(mode_t mode) {
    static constexpr std::array<std::pair<mode_t, const char*>, 6> kBits{{
        {S_IRGRP, "group-readable"},
        {S_IWGRP, "group-writable"},
        {S_IXGRP, "group-executable"},
        {S_IROTH, "world-readable"},
        {S_IWOTH, "world-writable"},
        {S_IXOTH, "world-executable"},
    }};
    std::string out;
    for (const auto& [bit, name] : kBits) {
        if ((mode & bit) != 0) {
            out += out.empty() ? "" : ", ";
            out += name;
        }
    }
    return out;
}

std::string_view trim(std::string_view text) {
    constexpr std::string_view kSpace = " \t\r\n";
    const auto first = text.find_first_not_of(kSpace);
    if (first == std::string_view::npos) {
        return {};
    }
    const auto last = text.find_last_not_of(kSpace);
    return text.substr(first, last - first + 1);
}

// Reads at most `limit` + 1 bytes, so that a longer file is noticed.
Result<std::string> read_small(int fd, std::size_t limit) {
    std::string data(limit + 1, '\0');
    std::size_t got = 0;
    while (got < data.size()) {
        const ssize_t n = ::read(fd, data.data() + got, data.size() - got);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0) {
            return Error{"cannot be read: " + errno_text(errno)};
        }
        if (n == 0) {
            break;
        }
        got += static_cast<std::size_t>(n);
    }
    data.resize(got);
    return data;
}

// Issue 30: a state directory that another user can write lets them plant
// the timestamp file (or swap it for a link). Owned by us or root, not
// writable by group or others.
std::optional<Error> check_directory(int fd, const std::string& directory) {
    const std::string what_to_do = fmt::format(
        "; allowed: a directory owned by the user gport-mavlink runs as (uid {}) or root, "
        "that neither its group nor others may write (e.g. chown that user, chmod 700 {}; the "
        "units' StateDirectory= makes one)",
        ::geteuid(), directory);
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        return Error{fmt::format("state directory {}: cannot be examined: {}", directory,
                                 errno_text(errno))};
    }
    if (st.st_uid != ::geteuid() && st.st_uid != 0) {
        return Error{
            fmt::format("state directory {}: is owned by uid {}, who could plant its "
                        "signing timestamp{}",
                        directory, st.st_uid, what_to_do)};
    }
    if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
        return Error{
            fmt::format("state directory {}: mode {:04o} is {}: others could plant its "
                        "signing timestamp{}",
                        directory, st.st_mode & 07777,
                        loose_permissions(st.st_mode & (S_IWGRP | S_IWOTH)), what_to_do)};
    }
    return std::nullopt;
}

}  // namespace

Result<SecretKey> load_signing_key(const std::string& path) {
    const std::string allowed =
        "; allowed: a regular file owned by the user gport-mavlink runs as, or by root, that "
        "only its owner can read or write (chmod 600 or 400), holding the 32-byte key as 64 "
        "hexadecimal digits";
    // O_NONBLOCK: a FIFO opens at once (and is refused below) instead of hanging.
    Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK));
    if (fd.get() < 0) {
        return Error{fmt::format("signing key {}: cannot be opened: {}{}", path, errno_text(errno),
                                 allowed)};
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) {
        return Error{
            fmt::format("signing key {}: cannot be examined: {}", path, errno_text(errno))};
    }
    if (!S_ISREG(st.st_mode)) {
        return Error{fmt::format("signing key {}: is not a regular file{}", path, allowed)};
    }
    // Another user's file, even mode 0600, is theirs to change (run as
    // root, anyone's key would otherwise do).
    if (st.st_uid != ::geteuid() && st.st_uid != 0) {
        return Error{
            fmt::format("signing key {}: is owned by uid {}, not by uid {} (this "
                        "process) or root{}",
                        path, st.st_uid, ::geteuid(), allowed)};
    }
    if ((st.st_mode & 077) != 0) {
        return Error{fmt::format("signing key {}: mode {:04o} is {}{}", path, st.st_mode & 07777,
                                 loose_permissions(st.st_mode), allowed)};
    }
    auto data = read_small(fd.get(), kMaxKeyFileSize);
    if (!data) {
        return Error{fmt::format("signing key {}: {}", path, data.error().message)};
    }
    if (data->size() > kMaxKeyFileSize) {
        wipe(*data);
        return Error{
            fmt::format("signing key {}: is over {} bytes{}", path, kMaxKeyFileSize, allowed)};
    }
    auto key = parse_key_hex(trim(*data));
    wipe(*data);
    if (!key) {
        return Error{fmt::format("signing key {}: {} (surrounding whitespace is allowed)", path,
                                 key.error().message)};
    }
    return key;
}

std::optional<Error> check_state_directory(const std::string& directory) {
    Fd fd(::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (fd.get() < 0) {
        return Error{
            fmt::format("state directory {}: cannot be opened: {}", directory, errno_text(errno))};
    }
    return check_directory(fd.get(), directory);
}

TimestampFile::TimestampFile(const std::string& directory)
    : directory_(directory.empty() ? "." : directory),
      path_(directory.empty() || directory.back() == '/' ? directory + kFileName
                                                         : directory + "/" + kFileName) {}

TimestampFile::TimestampFile(TimestampFile&& other) noexcept
    : directory_(std::move(other.directory_)),
      path_(std::move(other.path_)),
      lock_fd_(std::exchange(other.lock_fd_, -1)) {}

TimestampFile::~TimestampFile() {
    if (lock_fd_ >= 0) {
        ::close(lock_fd_);  // the lock goes with the descriptor
    }
}

std::optional<Error> TimestampFile::lock() {
    const int fd = ::open(directory_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) {
        return Error{
            fmt::format("state directory {}: cannot be opened: {}", directory_, errno_text(errno))};
    }
    if (auto error = check_directory(fd, directory_)) {
        ::close(fd);
        return error;
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        const int error = errno;
        ::close(fd);
        if (error == EWOULDBLOCK) {
            return Error{fmt::format(
                "state directory {}: in use by another process (another gport-mavlink holds its "
                "lock); two must not share one, or each would overwrite the other's signing "
                "timestamp: give each instance its own --state-dir (config state_dir)",
                directory_)};
        }
        return Error{
            fmt::format("state directory {}: cannot be locked: {}", directory_, errno_text(error))};
    }
    if (lock_fd_ >= 0) {
        ::close(lock_fd_);
    }
    lock_fd_ = fd;
    return std::nullopt;
}

Result<std::uint64_t> load_state_number(const std::string& path, std::uint64_t max,
                                        std::string_view invalid) {
    // O_NOFOLLOW: a symbolic link in its place is refused (ELOOP), not followed.
    Fd fd(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK | O_NOFOLLOW));
    if (fd.get() < 0 && errno == ENOENT) {
        return std::uint64_t{0};
    }
    if (fd.get() < 0) {
        const int error = errno;
        return Error{fmt::format("{}: cannot be opened: {}{}", path, errno_text(error),
                                 error == ELOOP ? " (a symbolic link: not followed)" : "")};
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0 || !S_ISREG(st.st_mode)) {
        return Error{
            fmt::format("{}: is not a regular file; remove it while gport-mavlink is "
                        "stopped",
                        path)};
    }
    auto data = read_small(fd.get(), 64);
    if (!data) {
        return Error{fmt::format("{}: {}", path, data.error().message)};
    }
    const std::string_view text = trim(*data);
    std::uint64_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() || value > max) {
        return Error{fmt::format("{}: {}", path, invalid)};
    }
    return value;
}

Result<std::uint64_t> TimestampFile::load() const {
    return load_state_number(
        path_, kMaxTimestamp,
        "does not hold a signing timestamp (one decimal number under 2^48); remove it only if "
        "this machine's clock is right (the next start then begins at the clock)");
}

std::optional<Error> TimestampFile::save(std::uint64_t timestamp) const {
    return save_state_number(path_, timestamp);
}

std::optional<Error> save_state_number(const std::string& path, std::uint64_t value) {
    // A unique name (O_EXCL, mode 0600): nothing else's file is reused.
    std::string temporary = path + ".XXXXXX";
    Fd fd(::mkostemp(temporary.data(), O_CLOEXEC));
    if (fd.get() < 0) {
        return Error{fmt::format("{}: cannot be created: {}", temporary, errno_text(errno))};
    }
    const std::string text = std::to_string(value) + "\n";
    const ssize_t n = ::write(fd.get(), text.data(), text.size());
    if (n != static_cast<ssize_t>(text.size())) {
        const int error = n < 0 ? errno : ENOSPC;
        ::unlink(temporary.c_str());
        return Error{fmt::format("{}: cannot be written: {}", temporary, errno_text(error))};
    }
    if (::fsync(fd.get()) != 0) {
        const int error = errno;
        ::unlink(temporary.c_str());
        return Error{fmt::format("{}: cannot be synced: {}", temporary, errno_text(error))};
    }
    if (::rename(temporary.c_str(), path.c_str()) != 0) {
        const int error = errno;
        ::unlink(temporary.c_str());
        return Error{fmt::format("{}: cannot be replaced: {}", path, errno_text(error))};
    }
    // The rename itself reaches the disk with the directory.
    const auto slash = path.rfind('/');
    const std::string directory = slash == std::string::npos ? "." : path.substr(0, slash + 1);
    Fd dir(::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (dir.get() >= 0) {
        ::fsync(dir.get());
    }
    return std::nullopt;
}

}  // namespace gport::mavlink::bridge
