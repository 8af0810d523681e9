// Who else has a serial device: the processes with it open (their
// /proc/PID/fd) and the live owners of its UUCP lock file (LCK..ttyUSB0 in
// /run/lock). `gportd --probe` leaves a device alone when it has any
// (docs/operations.md, "Finding the gimbal").
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace gport::daemon {

struct DeviceHolder {
    pid_t pid = 0;
    std::string name;  // /proc/PID/comm, "?" when it cannot be read
    std::string lock;  // the lock file naming it; empty for an open descriptor
};

struct DeviceHolders {
    std::vector<DeviceHolder> holders;
    // Processes whose descriptors could not be read (another user's, when
    // not root): any of them may hold the device too.
    std::size_t unchecked = 0;
};

// Where to look: /proc and the lock directory (tests give fake ones).
struct HolderPlaces {
    std::string proc = "/proc";
    std::string locks = "/run/lock";
};

// The holders of each of `devices` (character devices; any other path has
// none), in order, leaving out process `except` (the caller). A descriptor
// counts when its link in PROC/PID/fd names a path under /dev/ and, stat()ed
// through the link, is a character device with the same st_rdev as the
// device (a path elsewhere is not stat()ed: that could hang on a dead
// network file system). A lock file LOCKS/LCK..NAME counts for the base
// name of the device as given and of what it resolves to; it holds the
// owner's PID in ASCII (HDB UUCP, "      1234\n") or as a binary int (old
// UUCP). A lock whose PID is not alive is stale: not a holder, and left
// where it is.
std::vector<DeviceHolders> device_holders(const std::vector<std::string>& devices, pid_t except,
                                          const HolderPlaces& places = {});

// "PID 812 mavproxy, PID 990 minicom (lock file /run/lock/LCK..ttyUSB0)";
// the first three, then "and N more".
std::string describe_holders(const std::vector<DeviceHolder>& holders);

}  // namespace gport::daemon
