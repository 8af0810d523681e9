// gport-sim's command line on CLI11, with the conventions the three programs
// share (gport/base/args.hpp).
#include "gport/sim/command_line.hpp"

#include <fmt/format.h>
#include <grp.h>

#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gport/base/args.hpp"
#include "gport/protocol/messages.hpp"
#include "gport/version.hpp"

namespace gport::sim {
namespace {

using Error = OptionError;

// The longest silence or vanishing period, and the wait before one (a day).
constexpr double kMaxFaultMs = 86'400'000;

constexpr const char* kDescription =
    "A simulated HEQUAV G-Port gimbal on a pseudo-terminal, for gportd and its\n"
    "tests without hardware. It prints the slave path to open as the first line\n"
    "of standard output, then serves the gimbal there until SIGINT or SIGTERM.\n"
    "It streams attitude (0x87), moves under speed, angle, centre and lock\n"
    "commands (0x85; a speed command lasts one second), answers settings (0x13 ->\n"
    "0x14, 0x15 -> 0x16) and counts camera commands (0x86).";

constexpr const char* kFooter =
    "A client's exclusive mode (TIOCEXCL, as gportd sets it) would outlive the\n"
    "client on a pty. When the client goes, gport-sim clears it (TIOCNXCL; needs\n"
    "CAP_SYS_ADMIN, e.g. root) or else moves the link to a fresh pty, so that a\n"
    "restarted gportd (even after kill -9) can open the link again.\n\n"
    "Signals: SIGUSR1 stops reading what the client writes (a stalled gimbal:\n"
    "the client's writes fill the pty buffer, then block); SIGUSR2 resumes.\n\n"
    "Exit status: 0 after SIGINT/SIGTERM, 64 for a bad command line, 66 for an\n"
    "unreadable recording, 71 when the pty or link cannot be made.\n\n"
    "Examples:\n"
    "  gport-sim --link /tmp/gimbal             # then: gportd --device /tmp/gimbal\n"
    "  gport-sim --link /tmp/gimbal --trace --form 24 --rate 100\n"
    "  gport-sim --link /tmp/gimbal --trace --baud 115200   # a real UART's speed\n"
    "  gport-sim --link /tmp/gimbal --noise 200 --corrupt-crc 0.05 --split\n"
    "  gport-sim --link /tmp/gimbal --vanish-every 5000 --vanish-for 2000\n"
    "  gport-sim --link /tmp/gimbal --record session.rec\n"
    "  gport-sim --link /tmp/gimbal --replay session.rec";

std::optional<std::string> not_empty(std::string_view text) {
    if (text.empty()) {
        return std::string("must not be empty");
    }
    return std::nullopt;
}

// "ROLL,PITCH,YAW": three numbers in (0, 180], the mechanical range ± degrees.
std::optional<Vec3> parse_limits(std::string_view text) {
    std::array<double, 3> v{};
    std::string_view rest = text;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const auto comma = rest.find(',');
        const bool last = i + 1 == v.size();
        if (last != (comma == std::string_view::npos)) {
            return std::nullopt;
        }
        const auto part = rest.substr(0, comma);
        double n = 0;
        const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), n);
        if (ec != std::errc{} || end != part.data() + part.size() || !(n > 0 && n <= 180.0)) {
            return std::nullopt;
        }
        v[i] = n;
        rest = last ? std::string_view{} : rest.substr(comma + 1);
    }
    return Vec3{v[0], v[1], v[2]};
}

std::optional<std::string> check_limits(std::string_view text) {
    if (parse_limits(text)) {
        return std::nullopt;
    }
    return fmt::format(
        "needs three mechanical limits ROLL,PITCH,YAW in degrees, each above 0 and at most 180 "
        "(the range is ± that much), e.g. 45,90,170; got '{}'",
        text);
}

class Parser {
  public:
    Parser() : app_(kDescription, "gport-sim") {
        args::configure(app_, kFooter);
        app_.allow_extras();  // named by args::leftover_problem
        device();
        model();
        faults();
        observation();
    }

    Result<CommandLine, OptionError> parse(std::span<const std::string_view> argv) {
        std::vector<std::string> reversed(argv.rbegin(), argv.rend());
        try {
            app_.parse(reversed);
        } catch (const CLI::CallForHelp&) {
            cl_.help = true;
            return cl_;
        } catch (const CLI::CallForVersion&) {
            cl_.version = true;
            return cl_;
        } catch (const CLI::ParseError& error) {
            return Error{args::message_of(error)};
        }
        if (auto problem = args::leftover_problem(app_); !problem.empty()) {
            return Error{problem};
        }
        return finish();
    }

    std::string help() const { return app_.help(); }

  private:
    void device() {
        app_.add_option("--link", cl_.options.link_path,
                        "keep a symlink at PATH to the slave (replaced if it is a symlink, "
                        "refused otherwise; removed on exit and while vanished)")
            ->type_name("PATH")
            ->check(args::check_with(not_empty))
            ->group("Device");
        app_.add_option("--group", group_,
                        "give every slave this group, as udev gives an adapter (e.g. dialout, "
                        "so that an installed gportd may open it; needs root)")
            ->type_name("GROUP")
            ->group("Device");
        app_.add_option("--mode", mode_, "give every slave these permissions (octal, e.g. 0660)")
            ->type_name("OCTAL")
            ->group("Device");
        app_.add_flag("--pace", cl_.options.pace,
                      "pace output as a 115200-baud UART (86.8 us a byte); default: at once")
            ->group("Device");
        app_.add_option("--baud", cl_.options.baud,
                        "drain the line at BAUD (8N1: BAUD/10 bytes a second) both ways: read "
                        "what the client writes no faster, so its frames wait in the pty as in "
                        "a UART, and pace output (as --pace) at the same rate; 0 = off (default: "
                        "off, the pty drains at once; benches use 115200)")
            ->type_name("BAUD")
            ->check(args::integer_in(0, kMaxBaud))
            ->group("Device");
    }

    void model() {
        auto& m = cl_.options.model;
        app_.add_option("--rate", m.stream_rate_hz,
                        "0x87 frames per second; 0 = telemetry off (default 50)")
            ->type_name("HZ")
            ->check(args::number_in(0, kMaxStreamRateHz, "frames per second"))
            ->group("Model");
        app_.add_option("--form", form_,
                        "0x87 data bytes: 12 = attitude only, 24 = with hall and IMU rates "
                        "(default 12)")
            ->check(args::one_of({"12", "24"}))
            ->group("Model");
        app_.add_option("--slew", m.slew_deg_s, "speed of angle and centre moves (default 90)")
            ->type_name("DEG_PER_S")
            ->check(args::number_in(0.01, protocol::kMaxDegrees, "degrees per second"))
            ->group("Model");
        app_.add_option_function<std::string>(
                "--limits", [&m](const std::string& text) { m.limits = *parse_limits(text); },
                "mechanical range of roll, pitch and yaw: +-R, +-P, +-Y degrees, each above 0 "
                "and at most 180; speed motion stops there, angle targets are clamped to it "
                "(default 45,90,170)")
            ->type_name("R,P,Y")
            ->check(args::check_with(check_limits))
            ->group("Model");
    }

    void fault_ms(const char* name, Duration& target, const char* description) {
        app_.add_option_function<double>(
                name,
                [&target](double ms) {
                    target = std::chrono::duration_cast<Duration>(
                        std::chrono::duration<double, std::milli>(ms));
                },
                description)
            ->type_name("MS")
            ->check(args::number_in(1, kMaxFaultMs, "milliseconds"))
            ->group("Fault injection (default: none)");
    }

    void faults() {
        auto& f = cl_.options.faults;
        const char* group = "Fault injection (default: none)";
        app_.add_option("--noise", f.noise_bytes_per_s, "random bytes inserted between frames")
            ->type_name("BYTES_PER_S")
            ->check(args::number_in(0, 1e6, "bytes per second"))
            ->group(group);
        app_.add_option("--corrupt-crc", f.corrupt_fraction, "share of frames with a wrong CRC")
            ->type_name("FRACTION")
            ->check(args::number_in(0, 1, "a fraction of frames"))
            ->group(group);
        app_.add_flag("--split", split_, "write every byte with its own write()")->group(group);
        app_.add_option("--merge", merge_,
                        "put N frames into one write(); a partial group goes out after 100 ms")
            ->type_name("N")
            ->check(args::integer_in(2, 64))
            ->group(group);
        fault_ms("--silence-every", f.silence_every, "after MS milliseconds of output...");
        fault_ms("--silence-for", f.silence_for, "...send nothing for MS ms (give both)");
        fault_ms("--vanish-every", f.vanish_every, "after MS milliseconds present...");
        fault_ms("--vanish-for", f.vanish_for,
                 "...close the pty (and remove the link) for MS ms, then come back on a new "
                 "pty under the same link (give both)");
        app_.add_option("--seed", f.seed, "seed for noise and corruption (default 1)")
            ->type_name("N")
            ->check(args::integer_in(0, 4294967295LL))
            ->group(group);
    }

    void observation() {
        const char* group = "Observation";
        app_.add_flag("--trace", cl_.trace,
                      "print one JSON line per frame received, bad frame and event (peer_open, "
                      "peer_closed, exclusive_cleared, pty_replaced, exclusive_stuck, "
                      "silence_start, silence_end, vanish, reappear, replay_end), after the "
                      "first line (docs/simulator.md)")
            ->group(group);
        app_.add_option("--record", cl_.options.record_path,
                        "record both directions to FILE: \"<t_us> <rx|tx> <hex>\" a line")
            ->type_name("FILE")
            ->check(args::check_with(not_empty))
            ->group(group);
        app_.add_option("--replay", cl_.options.replay_path,
                        "instead of the model, play FILE's tx lines with their timing, from "
                        "when a client opens the slave (no fault options)")
            ->type_name("FILE")
            ->check(args::check_with(not_empty))
            ->group(group);
    }

    // Options given together or not at all, conflicting choices, then the
    // simulator's own checks.
    Result<CommandLine, OptionError> finish() {
        for (auto [a, b] : {std::pair{"--silence-every", "--silence-for"},
                            std::pair{"--vanish-every", "--vanish-for"}}) {
            if ((app_.count(a) > 0) != (app_.count(b) > 0)) {
                return Error{fmt::format("{} and {} must be given together", a, b)};
            }
        }
        if (app_.count("--split") > 0 && app_.count("--merge") > 0) {
            return Error{"--split and --merge cannot be combined: choose one write shape"};
        }
        if (app_.count("--split") > 0) {
            cl_.options.faults.shape = WriteShape::kSplit;
        }
        if (app_.count("--merge") > 0) {
            cl_.options.faults.shape = WriteShape::kMerge;
            cl_.options.faults.merge_count = merge_;
        }
        if (auto e = slave_access()) {
            return Error{*e};
        }
        if (app_.count("--form") > 0) {
            cl_.options.model.form = form_ == "12" ? AttitudeForm::kShort12 : AttitudeForm::kLong24;
        }
        if (auto e = validate(cl_.options)) {
            return Error{*e};
        }
        return cl_;
    }

    // --group and --mode: a group that exists, octal permission bits.
    std::optional<std::string> slave_access() {
        if (app_.count("--group") > 0) {
            const group* g = ::getgrnam(group_.c_str());
            if (g == nullptr) {
                return fmt::format("--group {}: no such group (see /etc/group)", group_);
            }
            cl_.options.slave_gid = static_cast<int>(g->gr_gid);
        }
        if (app_.count("--mode") > 0) {
            const bool octal = !mode_.empty() && mode_.size() <= 4 &&
                               mode_.find_first_not_of("01234567") == std::string::npos;
            const unsigned bits = octal ? static_cast<unsigned>(std::stoul(mode_, nullptr, 8)) : 0;
            if (!octal || bits == 0 || bits > 0777) {
                return fmt::format(
                    "--mode {}: must be octal permission bits from 0001 to 0777, "
                    "such as 0660",
                    mode_);
            }
            cl_.options.slave_mode = bits;
        }
        return std::nullopt;
    }

    CommandLine cl_;
    std::string group_, mode_;
    std::string form_;
    unsigned merge_ = 0;
    bool split_ = false;
    CLI::App app_;
};

}  // namespace

Result<CommandLine, OptionError> parse_command_line(std::span<const std::string_view> args) {
    return Parser().parse(args);
}

std::string help_text() {
    return Parser().help();
}

std::string version_text() {
    return fmt::format("gport-sim {}\n", kVersion);
}

}  // namespace gport::sim
