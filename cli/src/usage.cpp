// gportctl's help texts: the overview and one page per subcommand.
#include <map>
#include <string>

#include "gport/cli/options.hpp"

namespace gport::cli {
namespace {

constexpr const char* kOverview = R"(usage: gportctl [--socket PATH] [--json] COMMAND [OPTIONS]

Talks to gportd, the G-Port gimbal daemon, over its Unix socket.

commands:
  status                     link, device, counters, clients, current motion
  attitude                   the latest attitude sample
  watch [TOPIC...]           stream attitude, link and motion events
  monitor [--control]        full-screen live view (q quits; --for DURATION)
  speed --yaw DEG/S ...      move at a speed (until Ctrl-C, or --for DURATION)
  stop                       stop any motion now
  angle --pitch DEG ...      go to an angle (--wait: until it is reached)
  center                     centre the gimbal (--wait: until it is centred)
  lock                       lock mode (control mode 4)
  photo                      take a photo
  record [on|off [--force]]  toggle recording, or switch it on or off
  settings [--dead-zone N] [--follow-speed N] [--inverted yes|no]
                             read the settings, or change the ones given
  help [COMMAND]             this text, or a command's

global options:
  --socket PATH   daemon socket (default /run/gportd.sock, or $GPORT_SOCKET)
  --json          print raw JSON result objects, one per line, for scripts
  --help, -h      help (also after a command)

acquire and release are not commands: control held by a one-shot process
would be released the moment it exits. A program that needs exclusive
control keeps its own connection and calls "acquire" (see docs/api.md).

exit status: 0 success, 1 the daemon refused (message and code on stderr),
2 angle/center --wait ended without reaching the target, 64 usage error,
69 daemon unreachable, 130 interrupted.
)";

const std::map<std::string, std::string, std::less<>>& pages() {
    static const std::map<std::string, std::string, std::less<>> texts = {
        {"status",
         "usage: gportctl status\n\nLink state, device, versions, uptime, attitude "
         "age, counters, clients, motion and control.\n"},
        {"attitude",
         "usage: gportctl attitude\n\nThe latest attitude sample (degrees) and its "
         "age. Fails (exit 1) when none has arrived yet.\n"},
        {"watch",
         "usage: gportctl watch [attitude] [link] [motion] [--rate HZ]\n\n"
         "Prints each event as it arrives until Ctrl-C (exit 0). Without topics, all\n"
         "three. --rate limits attitude to at most HZ samples per second, always\n"
         "delivering the newest one.\n"},
        {"speed",
         "usage: gportctl speed [--roll DEG/S] [--pitch DEG/S] [--yaw DEG/S] "
         "[--for DURATION] [--lease MS] [--clamp]\n\n"
         "Axes not given are 0; each within -327.67..327.67 deg/s. A speed above\n"
         "gportd's limits.max_speed is refused, or with --clamp slowed to it.\n"
         "--lease MS (or 500ms, 2s): the daemon ends the motion when no further\n"
         "speed arrives within it (default: the duration).\n"
         "Without --for the motion lasts until Ctrl-C or SIGTERM: gportctl re-sends\n"
         "the speed every 200 ms for 500 ms at a time (if gportctl dies, the gimbal\n"
         "stops within half a second), then sends stop and exits 0.\n"
         "With --for DURATION (2s, 500ms, 1.5s, 1m) the daemon keeps the motion going;\n"
         "gportctl stays connected until it ends (the daemon stops the motion of a\n"
         "client that disconnects), and Ctrl-C stops it early.\n"},
        {"monitor",
         "usage: gportctl monitor [--control] [--for DURATION] [--color auto|always|never]\n\n"
         "A full-screen live view, redrawn ten times a second: link, IMU and hall\n"
         "angles, an attitude indicator, rates, the current motion, control,\n"
         "counters and the latest events. Keys: q quits, c centres; with --control\n"
         "(which acquires control, released on exit) the arrows nudge yaw and pitch.\n"
         "--for DURATION ends it after DURATION (3s, 1m). Colour unless NO_COLOR is\n"
         "set or --color never. When stdout is not a terminal (or TERM=dumb) it\n"
         "prints a plain status block every second instead. Ctrl-C, q and the end\n"
         "of --for exit 0 with the terminal restored.\n"},
        {"stop", "usage: gportctl stop\n\nSends zero speed at once.\n"},
        {"angle",
         "usage: gportctl angle [--roll DEG] [--pitch DEG] [--yaw DEG] [--clamp] [--wait]\n\n"
         "Angle control relative to the aircraft; axes not given are 0, each within\n"
         "-327.67..327.67. A target beyond gportd's soft limits is refused, or with\n"
         "--clamp clamped into them.\n"
         "--wait: waits until the motion ends and prints how (reached, timeout,\n"
         "replaced, stop, superseded, preempted, link_down, shutdown) and the final\n"
         "hall angles; exits 0 when reached, 2 otherwise. Ctrl-C while waiting\n"
         "exits 130 and the daemon applies its failsafe (default: stop).\n"
         "Without --wait the gimbal goes on to the target after gportctl exits.\n"},
        {"center",
         "usage: gportctl center [--wait]\n\n"
         "Centres the gimbal. --wait: as for angle (exit 0 when centred, 2 otherwise).\n"},
        {"lock", "usage: gportctl lock\n\nLock mode (control mode 4).\n"},
        {"photo", "usage: gportctl photo\n\nTakes a photo.\n"},
        {"record",
         "usage: gportctl record [on|off [--force]]\n\n"
         "Without on or off, toggles video recording. The gimbal never reports\n"
         "whether it records: gportd assumes a state from the toggles it sent,\n"
         "and it is unknown at start and whenever the device reopens. `on` and\n"
         "`off` toggle only when the assumed state differs; while it is unknown\n"
         "they are refused unless --force, which toggles and takes the state\n"
         "asked for as the new one.\n"},
        {"settings",
         "usage: gportctl settings [--dead-zone 0-255] [--follow-speed 0-255] "
         "[--inverted yes|no]\n\n"
         "Without options, reads the settings from the gimbal. With options,\n"
         "changes only those and prints the settings the gimbal now holds.\n"},
    };
    return texts;
}

}  // namespace

std::string usage(std::string_view command) {
    auto page = pages().find(command);
    return page == pages().end() ? kOverview : page->second;
}

}  // namespace gport::cli
