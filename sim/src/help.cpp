#include "gport/sim/command_line.hpp"

namespace gport::sim {

std::string help_text() {
    return R"(Usage: gport-sim [OPTIONS]

A simulated HEQUAV G-Port gimbal on a pseudo-terminal, for gportd and its
tests without hardware. It prints the slave path to open as the first line
of standard output, then serves the gimbal there until SIGINT or SIGTERM.
It streams attitude (0x87), moves under speed, angle, centre and lock
commands (0x85; a speed command lasts one second), answers settings (0x13 ->
0x14, 0x15 -> 0x16) and counts camera commands (0x86).

Device:
  --link PATH            keep a symlink at PATH to the slave (replaced if it is
                         a symlink, refused if it is anything else; removed on
                         exit and while vanished)
  --pace                 pace output as a 115200-baud UART (86.8 us a byte);
                         default: off, writes go out at once

Model:
  --rate HZ              0x87 frames per second, 0 to 10000; 0 = telemetry off
                         (default 50)
  --form 12|24           0x87 data bytes: 12 = attitude only, 24 = with hall and
                         IMU rates (default 12)
  --slew DEG_PER_S       speed of angle and centre moves, 0.01 to 327.67
                         (default 90)
  --limits R,P,Y         mechanical range of roll, pitch and yaw: +-R, +-P,
                         +-Y degrees, each above 0 and at most 180; speed
                         motion stops there, angle targets are clamped to it
                         (default 45,90,170)

Fault injection (default: none):
  --noise BYTES_PER_S    random bytes inserted between frames, 0 to 1000000
  --corrupt-crc FRACTION share of frames sent with a wrong CRC, 0 to 1
  --split                write every byte with its own write()
  --merge N              put N frames (2 to 64) into one write(); a partial
                         group goes out after 100 ms
  --silence-every MS     after MS milliseconds of output...
  --silence-for MS       ...send nothing for MS milliseconds (give both)
  --vanish-every MS      after MS milliseconds present...
  --vanish-for MS        ...close the pty (and remove the link) for MS
                         milliseconds, then come back on a new pty under the
                         same link, like an unplugged USB adapter (give both)
  --seed N               seed for noise and corruption (default 1)

Observation:
  --trace                print one JSON line per frame received, bad frame and
                         event (peer_open, peer_closed, exclusive_cleared,
                         pty_replaced, exclusive_stuck, silence_start,
                         silence_end, vanish, reappear, replay_end), after the
                         first line; format in docs/simulator.md
  --record FILE          record both directions to FILE, one line per read or
                         write: "<t_us> <rx|tx> <hex>"
  --replay FILE          instead of the model, play FILE's tx lines with their
                         timing, starting when a client opens the slave (no
                         fault options with --replay)

  -h, --help             this text

A client's exclusive mode (TIOCEXCL, as gportd sets it) would outlive the
client on a pty. When the client goes, gport-sim clears it (TIOCNXCL; needs
CAP_SYS_ADMIN, e.g. root) or else moves the link to a fresh pty, so that a
restarted gportd (even after kill -9) can open the link again.

Signals: SIGUSR1 stops reading what the client writes (a stalled gimbal:
the client's writes fill the pty buffer, then block); SIGUSR2 resumes.

Values may be given as "--rate 100" or "--rate=100". Exit status: 0 after
SIGINT/SIGTERM, 64 for a bad command line, 66 for an unreadable recording,
71 when the pty or link cannot be made.

Examples:
  gport-sim --link /tmp/gimbal             # then: gportd --device /tmp/gimbal
  gport-sim --link /tmp/gimbal --trace --form 24 --rate 100
  gport-sim --link /tmp/gimbal --noise 200 --corrupt-crc 0.05 --split
  gport-sim --link /tmp/gimbal --vanish-every 5000 --vanish-for 2000
  gport-sim --link /tmp/gimbal --record session.rec
  gport-sim --link /tmp/gimbal --replay session.rec
)";
}

}  // namespace gport::sim
