#include "capture_mark.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>

namespace gport::capture {

std::string format_mark(std::uint64_t mark) {
    return fmt::format("{:020}\n", mark);
}

std::optional<std::uint64_t> parse_mark(std::string_view text) {
    if (text.size() != kMarkBytes || text.back() != '\n') {
        return std::nullopt;
    }
    std::uint64_t mark = 0;
    const auto digits = text.substr(0, kMarkBytes - 1);
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), mark);
    if (ec != std::errc{} || end != digits.data() + digits.size()) {
        return std::nullopt;
    }
    return mark;
}

int open_no_follow(const std::string& path, int flags, unsigned mode) {
    return ::open(path.c_str(), flags | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK, mode);
}

std::string open_error(int error) {
    if (error == ELOOP) {
        return "a symbolic link, refused (gportd never follows one in its state directory)";
    }
    return std::strerror(error);
}

int open_mark(const std::string& path) {
    const int fd = open_no_follow(path, O_RDWR | O_CREAT);
    if (fd < 0) {
        return -1;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        ::close(fd);
        errno = EINVAL;
        return -1;
    }
    // A longer file (not ours) would not parse: cut it to one record.
    if (st.st_size > static_cast<off_t>(kMarkBytes)) {
        (void)::ftruncate(fd, static_cast<off_t>(kMarkBytes));
    }
    // Blocking again: the writes below are to wait for the disk.
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

std::optional<std::string> write_mark(int fd, std::uint64_t mark) {
    const auto record = format_mark(mark);
    const auto n = ::pwrite(fd, record.data(), record.size(), 0);
    if (n != static_cast<ssize_t>(record.size())) {
        return n < 0 ? std::strerror(errno) : std::string("short write");
    }
    if (::fdatasync(fd) != 0) {
        return std::strerror(errno);
    }
    return std::nullopt;
}

}  // namespace gport::capture
