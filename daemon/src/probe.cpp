#include "gport/daemon/probe.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <system_error>

#include "gport/daemon/device_holders.hpp"
#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Why a device could not be opened, and what to do about it.
std::string open_problem(int error) {
    switch (error) {
        case ENOENT:
            return "no such device";
        case EACCES:
            return "permission denied: not in the device's group (usually dialout: "
                   "sudo usermod -aG dialout $USER, then log in again), or run as root";
        case EBUSY:
            return "busy: another program holds it exclusively (gportd? stop it first: "
                   "sudo systemctl stop gportd.socket gportd)";
        case EIO:
        case ENXIO:
        case ENODEV:
            return "no hardware behind it";
        default:
            return std::strerror(error);
    }
}

// One device being listened on: its descriptor, whether we made it
// exclusive, its settings as found and as we set them, its decoder.
struct Listener {
    std::string device;
    int fd = -1;
    bool exclusive = false;
    std::optional<termios> saved;
    std::optional<termios> set;
    bool settings_left = false;  // changed by someone else while we listened: not put back
    protocol::Decoder decoder;
};

void fail(ProbeResult& result, std::string detail) {
    result.kind = ProbeResult::Kind::kFailed;
    result.detail = std::move(detail);
}

// Opens `device` and holds it exclusively (TIOCEXCL), unless it is no tty
// or already exclusive: someone holds it. Changes no setting; fills
// `result` on failure (returns false).
bool open_exclusive(const std::string& device, Listener& l, ProbeResult& result) {
    l.device = device;
    l.fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (l.fd < 0) {
        fail(result, open_problem(errno));
        return false;
    }
    termios t{};
    int exclusive = 0;
    if (::tcgetattr(l.fd, &t) != 0) {
        fail(result, errno == ENOTTY ? "not a serial device" : open_problem(errno));
    } else if (::ioctl(l.fd, TIOCGEXCL, &exclusive) != 0) {
        fail(result, fmt::format("cannot tell whether another program holds it (TIOCGEXCL: {}): "
                                 "left alone",
                                 std::strerror(errno)));
    } else if (exclusive != 0) {
        fail(result, open_problem(EBUSY));
    } else if (::ioctl(l.fd, TIOCEXCL) != 0) {
        fail(result, fmt::format("cannot hold it exclusively (TIOCEXCL: {}): left alone",
                                 std::strerror(errno)));
    } else {
        l.exclusive = true;
        l.saved = t;
        return true;
    }
    return false;
}

// Sets 115200 8N1 raw on a device held alone; fills `result` on failure.
bool set_raw(Listener& l, ProbeResult& result) {
    termios t = *l.saved;
    ::cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    if (::cfsetspeed(&t, B115200) != 0 || ::tcsetattr(l.fd, TCSANOW, &t) != 0 ||
        ::tcgetattr(l.fd, &t) != 0) {
        fail(result, fmt::format("cannot set 115200 8N1: {}", std::strerror(errno)));
        return false;
    }
    l.set = t;                  // as the driver took them
    ::tcflush(l.fd, TCIFLUSH);  // what came before we listened: nobody else's, we hold it alone
    return true;
}

bool same_settings(const termios& a, const termios& b) {
    return a.c_iflag == b.c_iflag && a.c_oflag == b.c_oflag && a.c_cflag == b.c_cflag &&
           a.c_lflag == b.c_lflag && std::memcmp(a.c_cc, b.c_cc, sizeof a.c_cc) == 0 &&
           ::cfgetispeed(&a) == ::cfgetispeed(&b) && ::cfgetospeed(&a) == ::cfgetospeed(&b);
}

// Puts the settings back, unless they are no longer the probe's: someone
// changed them while it listened (root, who TIOCEXCL does not stop, or
// through a pty's master), and theirs stay.
void restore(Listener& l) {
    termios now{};
    if (!l.set || ::tcgetattr(l.fd, &now) != 0) {
        return;  // never set, or gone
    }
    if (!same_settings(now, *l.set)) {
        l.settings_left = true;
        return;
    }
    ::tcsetattr(l.fd, TCSANOW, &*l.saved);
}

// TIOCEXCL is the line's flag, not the descriptor's: a program that opened
// the device before the probe held it (or root, whom it does not stop) may
// have set it for itself since. Cleared only while nobody else has the
// device open; a flag left on a line nobody holds goes with its last close
// (a pty's stays while its master is open, hence the clearing).
void release_exclusive(const Listener& l) {
    if (!l.exclusive) {
        return;
    }
    const auto others = device_holders({l.device}, ::getpid());
    if (!others.empty() && others.front().holders.empty()) {
        ::ioctl(l.fd, TIOCNXCL);
    }
}

void close_listener(Listener& l) {
    if (l.fd < 0) {
        return;
    }
    restore(l);
    release_exclusive(l);
    ::close(l.fd);
    l.fd = -1;
}

// One read per readiness: back in poll() the deadline is checked again, so a
// device that never stops sending cannot hold the probe past it.
void read_available(Listener& l, ProbeResult& result) {
    std::array<std::uint8_t, 4096> buffer{};
    const auto n = ::read(l.fd, buffer.data(), buffer.size());
    if (n <= 0) {
        return;  // EAGAIN, or a hang-up: nothing now
    }
    result.bytes += static_cast<std::uint64_t>(n);
    l.decoder.feed(
        std::span(buffer.data(), static_cast<std::size_t>(n)),
        [&](const protocol::FrameView& frame) {
            if (frame.command == static_cast<std::uint8_t>(protocol::Command::kAttitude)) {
                ++result.frames;
            }
        });
}

// Until `listen` has passed, or `interrupt` is readable; how long it listened.
std::chrono::milliseconds listen_all(std::vector<Listener>& listeners,
                                     std::vector<ProbeResult>& results,
                                     std::chrono::milliseconds listen, int interrupt) {
    const auto start = Clock::now();
    const auto deadline = start + listen;
    const auto listened = [&] {
        return std::min(
            listen, std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start));
    };
    for (auto now = Clock::now(); now < deadline; now = Clock::now()) {
        std::vector<pollfd> fds{{interrupt, POLLIN, 0}};  // a negative fd is skipped
        std::vector<std::size_t> which{0};
        for (std::size_t i = 0; i < listeners.size(); ++i) {
            if (listeners[i].fd >= 0) {
                fds.push_back({listeners[i].fd, POLLIN, 0});
                which.push_back(i);
            }
        }
        if (fds.size() == 1) {
            return listened();
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
        if (::poll(fds.data(), fds.size(), static_cast<int>(left.count()) + 1) < 0 &&
            errno != EINTR) {
            return listened();
        }
        if (fds[0].revents != 0) {
            return listened();
        }
        for (std::size_t k = 1; k < fds.size(); ++k) {
            if ((fds[k].revents & POLLIN) != 0) {
                read_available(listeners[which[k]], results[which[k]]);
            } else if ((fds[k].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
                close_listener(listeners[which[k]]);  // nobody on the other end: stop polling it
            }
        }
    }
    return listen;
}

std::string canonical_of(const std::string& device) {
    std::error_code ec;
    auto path = fs::canonical(device, ec);
    return ec ? device : path.string();
}

// The stable name of `device` in `by_id` (a USB adapter's), if any.
std::optional<std::string> stable_name(const std::string& device, const std::string& by_id) {
    const auto target = canonical_of(device);
    std::error_code ec;
    for (fs::directory_iterator it(by_id, ec), end; !ec && it != end; it.increment(ec)) {
        if (canonical_of(it->path().string()) == target) {
            return it->path().string();
        }
    }
    return std::nullopt;
}

// One result per device; two names of one device make one, the first.
std::vector<ProbeResult> unique_results(const std::vector<std::string>& devices,
                                        std::chrono::milliseconds listen) {
    std::vector<ProbeResult> results;
    std::vector<std::string> seen;  // canonical paths
    for (const auto& device : devices) {
        const auto target = canonical_of(device);
        if (std::find(seen.begin(), seen.end(), target) != seen.end()) {
            continue;
        }
        seen.push_back(target);
        ProbeResult& r = results.emplace_back();
        r.device = device;
        r.target = target != device && fs::path(device).is_absolute() ? target : std::string();
        r.listened = listen;
    }
    return results;
}

void mark_in_use(ProbeResult& r, const DeviceHolders& found) {
    r.kind = ProbeResult::Kind::kInUse;
    r.detail = fmt::format("in use by {}: left alone", describe_holders(found.holders));
    const auto is_gportd = [](const DeviceHolder& h) { return h.name == "gportd"; };
    if (std::any_of(found.holders.begin(), found.holders.end(), is_gportd)) {
        r.detail +=
            " (gportd serves it; to probe it, stop gportd first: "
            "sudo systemctl stop gportd.socket gportd)";
    }
}

// Opens the devices nobody holds and holds them exclusively, then looks
// for holders again: one that opened a device in between shows up now,
// and the device is let go untouched.
void open_free(std::vector<ProbeResult>& results, std::vector<Listener>& listeners) {
    std::vector<std::string> paths;
    for (const auto& r : results) {
        paths.push_back(r.device);
    }
    const auto before = device_holders(paths, ::getpid());
    bool opened = false;
    for (std::size_t i = 0; i < results.size(); ++i) {
        results[i].unchecked = before[i].unchecked;
        if (!before[i].holders.empty()) {
            mark_in_use(results[i], before[i]);
        } else if (open_exclusive(paths[i], listeners[i], results[i])) {
            opened = true;
        } else {
            close_listener(listeners[i]);  // not polled: a file would look like bytes
        }
    }
    const auto after = opened ? device_holders(paths, ::getpid()) : before;
    for (std::size_t i = 0; i < results.size(); ++i) {
        if (listeners[i].fd >= 0 && !after[i].holders.empty()) {
            close_listener(listeners[i]);
            mark_in_use(results[i], after[i]);
        }
    }
}

std::string what_it_is(const ProbeResult& r) {
    switch (r.kind) {
        case ProbeResult::Kind::kGport:
            return fmt::format("G-Port: {} attitude frames (0x87) in {:.1f} s", r.frames,
                               std::chrono::duration<double>(r.listened).count());
        case ProbeResult::Kind::kOther:
            return fmt::format("{} bytes, {} G-Port frames: another device, or not at 115200 baud",
                               r.bytes, r.frames);
        case ProbeResult::Kind::kSilent:
            return "silent (nothing received)";
        case ProbeResult::Kind::kInUse:
        case ProbeResult::Kind::kFailed:
            break;
    }
    return r.detail;
}

std::string describe(const ProbeResult& r) {
    return what_it_is(r) + (r.settings_left ? "; its settings were changed by another program "
                                              "while the probe listened: left as they are"
                                            : "");
}

// How many processes' descriptors could not be read, and what that means.
std::string unchecked_note(const std::vector<ProbeResult>& results) {
    std::size_t unchecked = 0;
    for (const auto& r : results) {
        unchecked = std::max(unchecked, r.unchecked);
    }
    if (unchecked == 0) {
        return "";
    }
    return fmt::format(
        "{} process{} of other users could not be checked (a device one of them has open, "
        "not exclusively, would not show as in use): run with sudo to check every holder.\n",
        unchecked, unchecked == 1 ? "" : "es");
}

}  // namespace

std::vector<ProbeResult> probe_devices(const std::vector<std::string>& devices,
                                       std::chrono::milliseconds listen, int interrupt) {
    auto results = unique_results(devices, listen);
    std::vector<Listener> listeners(results.size());
    open_free(results, listeners);
    for (std::size_t i = 0; i < listeners.size(); ++i) {
        if (listeners[i].fd >= 0 && !set_raw(listeners[i], results[i])) {
            close_listener(listeners[i]);
        }
    }
    const auto listened = listen_all(listeners, results, listen, interrupt);
    for (std::size_t i = 0; i < listeners.size(); ++i) {
        close_listener(listeners[i]);
        auto& r = results[i];
        r.listened = listened;
        r.settings_left = listeners[i].settings_left;
        if (r.kind != ProbeResult::Kind::kFailed && r.kind != ProbeResult::Kind::kInUse) {
            r.kind = r.frames >= kProbeFramesNeeded ? ProbeResult::Kind::kGport
                     : r.bytes > 0                  ? ProbeResult::Kind::kOther
                                                    : ProbeResult::Kind::kSilent;
        }
    }
    return results;
}

std::string probe_report(const std::vector<ProbeResult>& results, const std::string& by_id) {
    std::size_t width = 0;
    std::vector<std::string> names;
    for (const auto& r : results) {
        names.push_back(r.target.empty() ? r.device : fmt::format("{} ({})", r.device, r.target));
        width = std::max(width, names.back().size());
    }
    std::string out;
    std::vector<std::string> found;
    for (std::size_t i = 0; i < results.size(); ++i) {
        out += fmt::format("{:<{}}  {}\n", names[i], width, describe(results[i]));
        if (results[i].kind == ProbeResult::Kind::kGport) {
            found.push_back(stable_name(results[i].device, by_id).value_or(results[i].device));
        }
    }
    out += unchecked_note(results);
    if (found.empty()) {
        out +=
            "No G-Port found. Is it powered and wired (its TX to the adapter's RX, "
            "grounds joined)? A device in use, busy or refused is not known either way.\n";
        return out;
    }
    for (const auto& device : found) {
        out += fmt::format(
            "G-Port on {}. Set it in gportd's config (/etc/gportd/gportd.json):\n"
            "    \"serial\": {{\"device\": \"{}\"}}\n"
            "or start gportd with --device {}\n",
            device, device, device);
    }
    return out;
}

}  // namespace gport::daemon
