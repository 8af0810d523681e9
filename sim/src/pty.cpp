#include "gport/sim/pty.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <system_error>

namespace gport::sim {
namespace {

[[noreturn]] void fail(const std::string& what) {
    throw std::system_error(errno, std::generic_category(), what);
}

void make_slave_raw(const std::string& path) {
    const int slave = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (slave < 0) {
        fail("open " + path);
    }
    termios tio{};
    if (::tcgetattr(slave, &tio) != 0) {
        const int saved = errno;
        ::close(slave);
        errno = saved;
        fail("tcgetattr " + path);
    }
    ::cfmakeraw(&tio);
    ::cfsetspeed(&tio, B115200);
    tio.c_cc[VMIN] = 1;
    tio.c_cc[VTIME] = 0;
    const int rc = ::tcsetattr(slave, TCSANOW, &tio);
    const int saved = errno;
    ::close(slave);
    if (rc != 0) {
        errno = saved;
        fail("tcsetattr " + path);
    }
}

std::string read_link(const std::string& path) {
    std::array<char, 4096> buf{};
    const auto n = ::readlink(path.c_str(), buf.data(), buf.size() - 1);
    return n < 0 ? std::string{} : std::string(buf.data(), static_cast<std::size_t>(n));
}

}  // namespace

PtyMaster open_pty(const SlaveAccess& access) {
    const int fd = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) {
        fail("posix_openpt");
    }
    try {
        if (::grantpt(fd) != 0) {
            fail("grantpt");
        }
        if (::unlockpt(fd) != 0) {
            fail("unlockpt");
        }
        std::array<char, 128> name{};
        if (::ptsname_r(fd, name.data(), name.size()) != 0) {
            fail("ptsname_r");
        }
        PtyMaster pty{fd, name.data()};
        make_slave_raw(pty.slave_path);
        if (access.gid >= 0 && ::chown(pty.slave_path.c_str(), static_cast<uid_t>(-1),
                                       static_cast<gid_t>(access.gid)) != 0) {
            fail("chown " + pty.slave_path + " (--group needs root, or to be in that group)");
        }
        if (access.mode != 0 && ::chmod(pty.slave_path.c_str(), access.mode) != 0) {
            fail("chmod " + pty.slave_path);
        }
        return pty;
    } catch (...) {
        ::close(fd);
        throw;
    }
}

bool peer_present(int master_fd) {
    pollfd p{master_fd, POLLIN, 0};
    if (::poll(&p, 1, 0) < 0) {
        return false;
    }
    return (p.revents & POLLHUP) == 0;
}

Exclusivity release_exclusive(const std::string& slave_path) {
    const int slave = ::open(slave_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (slave < 0) {
        if (errno == EBUSY) {
            return Exclusivity::kStuck;
        }
        fail("open " + slave_path);
    }
    int exclusive = 0;
    const char* step = "read the exclusive mode (TIOCGEXCL) of ";
    int rc = ::ioctl(slave, TIOCGEXCL, &exclusive);
    if (rc == 0 && exclusive != 0) {
        step = "clear the exclusive mode (TIOCNXCL) of ";
        rc = ::ioctl(slave, TIOCNXCL);
    }
    const int saved = errno;
    ::close(slave);
    if (rc != 0) {
        errno = saved;
        fail(step + slave_path);
    }
    return exclusive != 0 ? Exclusivity::kCleared : Exclusivity::kNone;
}

void SlaveLink::point_to(const std::string& target) {
    if (path_.empty()) {
        return;
    }
    struct stat st {};
    if (::lstat(path_.c_str(), &st) == 0 && !S_ISLNK(st.st_mode)) {
        errno = EEXIST;
        fail(path_ + " exists and is not a symlink; refusing to replace it");
    }
    // A fresh link renamed over the old one: a client never sees the path missing
    // or pointing nowhere while the link moves.
    const std::string temp = path_ + ".tmp" + std::to_string(::getpid());
    ::unlink(temp.c_str());
    if (::symlink(target.c_str(), temp.c_str()) != 0) {
        fail("symlink " + temp);
    }
    if (::rename(temp.c_str(), path_.c_str()) != 0) {
        const int saved = errno;
        ::unlink(temp.c_str());
        errno = saved;
        fail("rename " + temp + " to " + path_);
    }
    target_ = target;
}

void SlaveLink::remove() noexcept {
    if (path_.empty() || target_.empty()) {
        return;
    }
    if (read_link(path_) == target_) {
        ::unlink(path_.c_str());
    }
    target_.clear();
}

}  // namespace gport::sim
