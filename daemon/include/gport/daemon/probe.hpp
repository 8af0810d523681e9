// Finding the G-Port (gportd --probe, gport/app/probe.hpp). A powered, wired G-Port
// streams its attitude (0x87 frames) at 115200 baud whether anybody asked
// or not, so listening is enough: nothing is written to any device. Each
// device is opened (non-blocking, never exclusively), set to 115200 8N1
// raw, read for a short while, and its settings are put back. Devices are
// read at the same time, so the whole probe takes one listening period.
// docs/operations.md, "Finding the gimbal".
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace gport::daemon {

struct ProbeResult {
    enum class Kind {
        kGport,   // valid 0x87 frames: a G-Port
        kOther,   // bytes, but no G-Port frame: another device, or another baud rate
        kSilent,  // nothing at all
        kFailed,  // could not be opened or set up; `detail` says why and what to do
    };
    std::string device;  // as given
    std::string target;  // the device it resolves to, when a link (serial0 -> ttyAMA0)
    Kind kind = Kind::kSilent;
    std::uint64_t frames = 0;  // valid 0x87 frames
    std::uint64_t bytes = 0;
    std::string detail;
    std::chrono::milliseconds listened{0};
};

// At least this many valid 0x87 frames make a G-Port (one could be chance).
inline constexpr std::uint64_t kProbeFramesNeeded = 3;

// Listens on `devices` (two names of one device are listened on once, under
// the first name) for `listen`.
std::vector<ProbeResult> probe_devices(const std::vector<std::string>& devices,
                                       std::chrono::milliseconds listen);

// The report: one line per device, then what to set. `by_id` is where the
// stable names of USB adapters are (/dev/serial/by-id).
std::string probe_report(const std::vector<ProbeResult>& results,
                         const std::string& by_id = "/dev/serial/by-id");

}  // namespace gport::daemon
