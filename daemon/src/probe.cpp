#include "gport/daemon/probe.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
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

// One device being listened on: its descriptor, its settings to put back,
// its decoder.
struct Listener {
    int fd = -1;
    std::optional<termios> saved;
    protocol::Decoder decoder;
};

// Opens and sets up 115200 8N1 raw; fills `result` on failure (returns false).
bool open_raw(const std::string& device, Listener& l, ProbeResult& result) {
    l.fd = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (l.fd < 0) {
        result.kind = ProbeResult::Kind::kFailed;
        result.detail = open_problem(errno);
        return false;
    }
    termios t{};
    if (::tcgetattr(l.fd, &t) != 0) {
        result.kind = ProbeResult::Kind::kFailed;
        result.detail = errno == ENOTTY ? "not a serial device" : open_problem(errno);
        return false;
    }
    l.saved = t;
    ::cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    if (::cfsetspeed(&t, B115200) != 0 || ::tcsetattr(l.fd, TCSANOW, &t) != 0) {
        result.kind = ProbeResult::Kind::kFailed;
        result.detail = fmt::format("cannot set 115200 8N1: {}", std::strerror(errno));
        return false;
    }
    ::tcflush(l.fd, TCIFLUSH);  // what came before we listened
    return true;
}

void close_listener(Listener& l) {
    if (l.fd < 0) {
        return;
    }
    if (l.saved) {
        ::tcsetattr(l.fd, TCSANOW, &*l.saved);  // as we found it
    }
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

void listen_all(std::vector<Listener>& listeners, std::vector<ProbeResult>& results,
                std::chrono::milliseconds listen) {
    const auto deadline = Clock::now() + listen;
    for (auto now = Clock::now(); now < deadline; now = Clock::now()) {
        std::vector<pollfd> fds;
        std::vector<std::size_t> which;
        for (std::size_t i = 0; i < listeners.size(); ++i) {
            if (listeners[i].fd >= 0) {
                fds.push_back({listeners[i].fd, POLLIN, 0});
                which.push_back(i);
            }
        }
        if (fds.empty()) {
            return;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
        if (::poll(fds.data(), fds.size(), static_cast<int>(left.count()) + 1) < 0 &&
            errno != EINTR) {
            return;
        }
        for (std::size_t k = 0; k < fds.size(); ++k) {
            if ((fds[k].revents & POLLIN) != 0) {
                read_available(listeners[which[k]], results[which[k]]);
            } else if ((fds[k].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
                close_listener(listeners[which[k]]);  // nobody on the other end: stop polling it
            }
        }
    }
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

std::string describe(const ProbeResult& r) {
    switch (r.kind) {
        case ProbeResult::Kind::kGport:
            return fmt::format("G-Port: {} attitude frames (0x87) in {:.1f} s", r.frames,
                               std::chrono::duration<double>(r.listened).count());
        case ProbeResult::Kind::kOther:
            return fmt::format("{} bytes, {} G-Port frames: another device, or not at 115200 baud",
                               r.bytes, r.frames);
        case ProbeResult::Kind::kSilent:
            return "silent (nothing received)";
        case ProbeResult::Kind::kFailed:
            break;
    }
    return r.detail;
}

}  // namespace

std::vector<ProbeResult> probe_devices(const std::vector<std::string>& devices,
                                       std::chrono::milliseconds listen) {
    std::vector<ProbeResult> results;
    std::vector<Listener> listeners;
    std::vector<std::string> seen;  // canonical paths: one device, one listener
    results.reserve(devices.size());
    listeners.reserve(devices.size());
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
        if (!open_raw(device, listeners.emplace_back(), r)) {
            close_listener(listeners.back());  // not polled: a file would look like bytes
        }
    }
    listen_all(listeners, results, listen);
    for (std::size_t i = 0; i < listeners.size(); ++i) {
        close_listener(listeners[i]);
        auto& r = results[i];
        if (r.kind != ProbeResult::Kind::kFailed) {
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
    if (found.empty()) {
        out +=
            "No G-Port found. Is it powered and wired (its TX to the adapter's RX, "
            "grounds joined)? A device that was busy or refused is not known either way.\n";
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
