// Finding the G-Port (gportd --probe, gport/app/probe.hpp). A powered, wired G-Port
// streams its attitude (0x87 frames) at 115200 baud whether anybody asked
// or not, so listening is enough: nothing is written to any device.
// A device another process has open (device_holders.hpp: its descriptors,
// its UUCP lock file) is left alone, not opened. Each other one is opened
// non-blocking; one already held exclusively (TIOCGEXCL) is let go as busy;
// the rest are held exclusively (TIOCEXCL) and checked for holders again
// (one may have opened it in between: it is let go untouched), then set to
// 115200 8N1 raw, read for a short while, and their settings put back,
// unless someone changed them meanwhile (theirs stay), and the exclusive
// hold is dropped. Devices are read at the same time, so the whole probe
// takes one listening period. docs/operations.md, "Finding the gimbal".
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace gport::daemon {

struct ProbeResult {
    enum class Kind {
        kGport,   // valid 0x87 frames: a G-Port
        kOther,   // bytes, but no G-Port frame: another device, or another baud rate
        kSilent,  // nothing at all
        kInUse,   // another process has it open or locked; `detail` names it: left alone
        kFailed,  // could not be opened or set up; `detail` says why and what to do
    };
    std::string device;  // as given
    std::string target;  // the device it resolves to, when a link (serial0 -> ttyAMA0)
    Kind kind = Kind::kSilent;
    std::uint64_t frames = 0;  // valid 0x87 frames
    std::uint64_t bytes = 0;
    std::string detail;
    std::chrono::milliseconds listened{0};
    // Its settings changed while the probe listened, not by the probe: left as they were found.
    bool settings_left = false;
    // Processes whose descriptors could not be read (other users', not root).
    std::size_t unchecked = 0;
};

// At least this many valid 0x87 frames make a G-Port (one could be chance).
inline constexpr std::uint64_t kProbeFramesNeeded = 3;

// Listens on `devices` (two names of one device are listened on once, under
// the first name) for `listen`, or until `interrupt` (a descriptor; -1 for
// none) is readable: a signalfd of Ctrl-C, say, so that the settings are put
// back before the signal ends the process.
std::vector<ProbeResult> probe_devices(const std::vector<std::string>& devices,
                                       std::chrono::milliseconds listen, int interrupt = -1);

// The report: one line per device, then what to set. `by_id` is where the
// stable names of USB adapters are (/dev/serial/by-id).
std::string probe_report(const std::vector<ProbeResult>& results,
                         const std::string& by_id = "/dev/serial/by-id");

}  // namespace gport::daemon
