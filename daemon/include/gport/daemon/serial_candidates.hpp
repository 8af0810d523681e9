// Where a G-Port usually is: the serial devices of this machine that a
// gimbal cable may end on, for `gportd --probe` and for the hint when the
// configured device is missing (docs/operations.md, "Finding the gimbal").
#pragma once

#include <string>
#include <vector>

namespace gport::daemon {

// The serial devices under `dev` (normally /dev) that exist, in this order:
// serial0 and serial1 (a Raspberry Pi's aliases of its UARTs), ttyAMA*
// (Raspberry Pi PL011), ttyTHS* (Jetson), ttyUSB* (USB adapters: FTDI,
// CP210x, CH34x, PL2303), ttyACM* (CDC-ACM), then ttyS* that have a UART
// behind them (`sys`/class/tty/ttySN/type not 0: a PC's 32 ttyS nodes mostly
// have none). Sorted by number within a kind; an alias (serial0) is listed
// beside the device it names.
std::vector<std::string> serial_candidates(const std::string& dev = "/dev",
                                           const std::string& sys = "/sys");

// What to tell a user whose device is missing: "serial devices here:
// /dev/ttyUSB0, /dev/ttyAMA0; set serial.device (or --device) to the
// gimbal's, or run `gportd --probe` to find it" or, with none, "no serial
// devices here (is the adapter plugged in? see `dmesg`)".
std::string candidates_hint(const std::vector<std::string>& candidates);

}  // namespace gport::daemon
