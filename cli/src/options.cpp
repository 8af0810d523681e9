// gportctl's command line on CLI11: global options anywhere, one subcommand,
// its options. Values are checked here against the protocol's own constants,
// so that a typo is a usage error (64) before any connection is made.
#include "gport/cli/options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "gport/base/args.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

// The longest --for and --lease the protocol accepts; gportd's own
// keepalive.max_duration_ms is usually lower (run.cpp reports its refusal
// as a usage error naming the option).
constexpr std::chrono::milliseconds kMaxDuration{ipc::kMaxDurationMs};

constexpr const char* kDescription =
    "Talks to gportd, the G-Port gimbal daemon, over its Unix socket.\n\n"
    "acquire and release are not commands: control held by a one-shot process\n"
    "would be released the moment it exits. A program that needs exclusive\n"
    "control keeps its own connection and calls \"acquire\" (see docs/api.md).";

constexpr const char* kExitStatuses =
    "Exit status: 0 success, 1 the daemon refused (message and code on stderr),\n"
    "2 angle/center --wait ended without reaching the target, 64 usage error,\n"
    "69 daemon unreachable, 130 interrupted (Ctrl-C, SIGTERM).";

const std::vector<std::string> kTopics = {"attitude", "link", "motion"};

// The values CLI11 fills; turned into an Invocation after parsing.
struct Values {
    std::string socket;
    bool json = false;
    double roll = 0, pitch = 0, yaw = 0;
    std::string for_text, lease_text;
    bool clamp = false, wait = false, force = false;
    std::vector<std::string> topics;
    double rate = 0;
    bool shared_memory = false;  // watch
    long count = 0;
    std::string state;  // record on|off
    int dead_zone = 0, follow_speed = 0;
    std::string inverted;
    std::string help_topic;
    bool control = false;  // monitor
    bool ascii = false;    // monitor
    std::string color = "auto";
};

class Parser {
  public:
    Parser() : app_(kDescription, "gportctl") {
        args::configure(app_, kExitStatuses);
        app_.require_subcommand(0, 1);
        app_.allow_extras();  // checked after parsing, to name the command
        app_.add_option("--socket", v_.socket,
                        fmt::format("daemon socket (default {}, or $GPORT_SOCKET)", kDefaultSocket))
            ->type_name("PATH");
        app_.add_flag("--json", v_.json, "print raw JSON result objects, one per line");
        add_commands();
    }

    Invocation parse(const std::vector<std::string>& args, const char* env_socket) {
        std::vector<std::string> reversed(args.rbegin(), args.rend());
        try {
            app_.parse(reversed);
        } catch (const CLI::ParseError& error) {
            if (!args::is_request(error)) {
                throw UsageError{args::message_of(error)};
            }
            Invocation inv;
            inv.help = true;
            inv.text = dynamic_cast<const CLI::CallForVersion*>(&error) != nullptr
                           ? std::string(error.what()) + "\n"
                           : app_.help();
            return inv;
        }
        return build(env_socket);
    }

  private:
    CLI::App* command(const char* name, const char* method, const char* description) {
        auto* sub = app_.add_subcommand(name, description);
        methods_[name] = method;
        return sub;
    }

    void add_axes(CLI::App* sub, std::string_view unit) {
        const auto range =
            args::number_in(-protocol::kMaxDegrees, protocol::kMaxDegrees, std::string(unit));
        for (auto [name, value] : {std::pair{"roll", &v_.roll}, std::pair{"pitch", &v_.pitch},
                                   std::pair{"yaw", &v_.yaw}}) {
            sub->add_option(fmt::format("--{}", name), *value, fmt::format("{} ({})", name, unit))
                ->type_name(unit == std::string_view("degrees") ? "DEG" : "DEG/S")
                ->check(range);
        }
        sub->add_flag("--clamp", v_.clamp, "slow or clamp to gportd's limits instead of refusing");
    }

    void add_commands() {
        command("status", "status", "link, device, counters, clients, current motion");
        command("attitude", "attitude", "the latest attitude sample");
        add_watch();
        add_speed();
        command("stop", "stop", "stop any motion now");
        add_angle();
        command("center", "center", "centre the gimbal")
            ->add_flag("--wait", v_.wait, "wait until centred; exit 2 if it is not");
        command("lock", "lock", "lock mode (control mode 4)");
        command("photo", "photo", "take a photo");
        add_record();
        add_settings();
        add_monitor();
        auto* help = command("help", "", "this text, or a command's");
        help->add_option("command", v_.help_topic, "the command to describe");
    }

    void add_monitor() {
        auto* sub = command("monitor", "", "full-screen live view of the gimbal (q quits)");
        sub->add_flag("--control", v_.control,
                      "acquire control (released on exit); the arrow keys nudge the gimbal");
        sub->add_option("--for", v_.for_text, "end after DURATION (2s, 500ms, 1m)")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, kMaxDuration));
        sub->add_option("--color", v_.color, "colour: auto (unless $NO_COLOR), always or never")
            ->type_name("WHEN")
            ->check(args::one_of({"auto", "always", "never"}));
        sub->add_flag("--ascii", v_.ascii, "ASCII only (the default when the locale is not UTF-8)");
    }

    void add_watch() {
        auto* sub = command("watch", "subscribe", "stream attitude, link and motion events");
        sub->add_option("topics", v_.topics, "attitude, link, motion (default: all three)")
            ->check(args::one_of(kTopics));
        sub->add_option("--rate", v_.rate, "at most HZ attitude samples a second (the newest)")
            ->type_name("HZ")
            ->check(args::number_in(ipc::kMinRateHz, ipc::kMaxRateHz, "a rate in Hz"));
        sub->add_flag("--shared-memory", v_.shared_memory,
                      "attitude from gportd's shared-memory channel (every sample)");
        sub->add_option("-n,--count", v_.count, "exit 0 after COUNT events")
            ->type_name("COUNT")
            ->check(args::integer_in(1, std::numeric_limits<int>::max()));
        sub->add_option("--for", v_.for_text, "exit 0 after DURATION (2s, 500ms, 1m)")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, kMaxDuration));
        sub->footer(
            "Prints each event as it arrives until Ctrl-C (exit 0), COUNT events or\n"
            "DURATION. --rate limits attitude, always delivering the newest sample.\n"
            "--shared-memory reads attitude from the shared-memory channel instead of\n"
            "the socket (every sample, the same output; not with --rate).\n");
    }

    void add_speed() {
        auto* sub = command("speed", "speed", "move at a speed (until Ctrl-C, or --for DURATION)");
        add_axes(sub, "deg/s");
        sub->add_option("--for", v_.for_text, "the daemon keeps the motion going this long")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, kMaxDuration));
        sub->add_option("--lease", v_.lease_text,
                        "the daemon ends the motion when no speed arrives within it")
            ->type_name("MS")
            ->check(args::duration_in(1ms, kMaxDuration, true));
        sub->footer(
            "Axes not given are 0. A speed above gportd's limits.max_speed is refused,\n"
            "or with --clamp slowed to it. Without --for the motion lasts until Ctrl-C or\n"
            "SIGTERM: gportctl re-sends the speed every 200 ms for 500 ms at a time (if\n"
            "gportctl dies, the gimbal stops within half a second), then sends stop.\n"
            "With --for the daemon keeps the motion going and gportctl shows its progress\n"
            "until it ends; Ctrl-C stops it early. A --for or --lease longer than gportd's\n"
            "keepalive.max_duration_ms is a usage error (64) naming the daemon's limit.\n");
    }

    void add_angle() {
        auto* sub = command("angle", "angle", "go to an angle (--wait: until it is reached)");
        add_axes(sub, "degrees");
        sub->add_flag("--wait", v_.wait, "wait for the end; print it; exit 2 unless reached");
        sub->footer(
            "Angle control relative to the aircraft; axes not given are 0. A target\n"
            "beyond gportd's soft limits is refused, or with --clamp clamped into them.\n"
            "--wait prints how the motion ended (reached, timeout, replaced, stop, ...)\n"
            "and the attitude reached. Ctrl-C while waiting exits 130 and the daemon\n"
            "applies its failsafe. Without --wait the gimbal goes on after gportctl exits.\n");
    }

    void add_record() {
        auto* sub = command("record", "record", "toggle recording, or switch it on or off");
        sub->add_option("state", v_.state, "on or off (default: toggle)")
            ->check(args::one_of({"on", "off"}));
        sub->add_flag("--force", v_.force, "toggle even when the state is unknown");
        sub->footer(
            "The gimbal never reports whether it records: gportd assumes a state from\n"
            "the toggles it sent, unknown at start and whenever the device reopens.\n"
            "on and off toggle only when the assumed state differs; while it is unknown\n"
            "they are refused unless --force.\n");
    }

    void add_settings() {
        auto* sub = command("settings", "get_settings", "read the settings, or change some");
        const auto byte = args::integer_in(0, std::numeric_limits<std::uint8_t>::max());
        sub->add_option("--dead-zone", v_.dead_zone, "dead zone")->check(byte);
        sub->add_option("--follow-speed", v_.follow_speed, "follow speed")->check(byte);
        sub->add_option("--inverted", v_.inverted, "mounted upside down")
            ->type_name("yes|no")
            ->check(args::one_of({"yes", "no", "true", "false", "on", "off"}));
    }

    // Extras CLI11 left: an unknown option or command, or a stray argument.
    void check_extras(const CLI::App* sub) const {
        const auto extras = app_.remaining();
        if (extras.empty()) {
            return;
        }
        const auto& first = extras.front();
        if (sub == nullptr) {
            throw UsageError{first.starts_with("-") ? fmt::format("unknown option {}", first)
                                                    : fmt::format("unknown command \"{}\"", first)};
        }
        if (!first.starts_with("-")) {
            throw UsageError{fmt::format("{}: unexpected argument \"{}\"", sub->get_name(), first)};
        }
        std::vector<std::string> names;
        for (const auto* option : sub->get_options()) {
            if (option->get_name() != "--help" && !option->get_lnames().empty()) {
                names.push_back(option->get_name());
            }
        }
        throw UsageError{
            fmt::format("{}: unknown option {}{}", sub->get_name(), first,
                        names.empty() ? "; it takes none"
                                      : "; options: " + fmt::format("{}", fmt::join(names, ", ")))};
    }

    Invocation build(const char* env_socket) {
        const auto subs = app_.get_subcommands();
        const CLI::App* sub = subs.empty() ? nullptr : subs.front();
        check_extras(sub);
        if (sub == nullptr) {
            throw UsageError{"no command given"};
        }
        Invocation inv;
        inv.command = sub->get_name();
        inv.method = methods_.at(inv.command);
        inv.json = v_.json;
        inv.socket = app_.count("--socket") > 0                     ? v_.socket
                     : env_socket != nullptr && *env_socket != '\0' ? env_socket
                                                                    : std::string(kDefaultSocket);
        if (inv.command == "help") {
            return help_of(v_.help_topic);
        }
        if (inv.command == "watch") {
            watch(*sub, inv);
        } else if (inv.command == "speed" || inv.command == "angle" || inv.command == "center") {
            motion(*sub, inv);
        } else if (inv.command == "record") {
            record(*sub, inv);
        } else if (inv.command == "settings") {
            settings(*sub, inv);
        } else if (inv.command == "monitor") {
            monitor(*sub, inv);
        }
        return inv;
    }

    Invocation help_of(const std::string& topic) const {
        Invocation inv;
        inv.help = true;
        if (topic.empty()) {
            inv.text = app_.help();
            return inv;
        }
        try {
            inv.text = app_.get_subcommand(topic)->help("gportctl");
        } catch (const CLI::OptionNotFound&) {
            throw UsageError{fmt::format("help: unknown command \"{}\"", topic)};
        }
        return inv;
    }

    void monitor(const CLI::App& sub, Invocation& inv) const {
        inv.monitor.socket = inv.socket;
        inv.monitor.control = v_.control;
        inv.monitor.ascii = v_.ascii;
        if (sub.count("--for") > 0) {
            inv.monitor.duration = args::parse_duration(v_.for_text);
        }
        inv.monitor.color = v_.color == "always"  ? ColorMode::kAlways
                            : v_.color == "never" ? ColorMode::kNever
                                                  : ColorMode::kAuto;
    }

    void watch(const CLI::App& sub, Invocation& inv) const {
        for (const auto& topic : v_.topics) {
            if (std::find(inv.topics.begin(), inv.topics.end(), topic) == inv.topics.end()) {
                inv.topics.push_back(topic);
            }
        }
        if (inv.topics.empty()) {
            inv.topics = kTopics;
        }
        inv.params["topics"] = inv.topics;
        if (sub.count("--rate") > 0) {
            if (v_.shared_memory) {
                throw UsageError{
                    "watch: --rate and --shared-memory cannot be combined (the shared-memory "
                    "channel offers every sample)"};
            }
            inv.rate_hz = v_.rate;
            inv.params["max_rate_hz"] = v_.rate;
        }
        inv.shared_memory = v_.shared_memory;
        if (sub.count("--count") > 0) {
            inv.count = v_.count;
        }
        if (sub.count("--for") > 0) {
            inv.duration = args::parse_duration(v_.for_text);
        }
    }

    void motion(const CLI::App& sub, Invocation& inv) const {
        for (const auto& [name, value] :
             {std::pair{"roll", v_.roll}, std::pair{"pitch", v_.pitch}, std::pair{"yaw", v_.yaw}}) {
            if (sub.get_option_no_throw(fmt::format("--{}", name)) != nullptr &&
                sub.count(fmt::format("--{}", name)) > 0) {
                inv.params[name] = value;
            }
        }
        if (sub.get_option_no_throw("--for") != nullptr && sub.count("--for") > 0) {
            inv.duration = args::parse_duration(v_.for_text);
            inv.params["duration_ms"] = inv.duration->count();
        }
        if (sub.get_option_no_throw("--lease") != nullptr && sub.count("--lease") > 0) {
            const bool digits = v_.lease_text.find_first_not_of("0123456789") == std::string::npos;
            inv.params["lease_ms"] =
                args::parse_duration(digits ? v_.lease_text + "ms" : v_.lease_text)->count();
        }
        if (v_.clamp) {
            inv.params["clamp"] = true;
        }
        if (v_.wait) {
            inv.params["wait"] = true;
            inv.wait = true;
        }
    }

    void record(const CLI::App& sub, Invocation& inv) const {
        if (sub.count("state") > 0) {
            inv.params["on"] = v_.state == "on";
        }
        if (v_.force) {
            if (sub.count("state") == 0) {
                throw UsageError{"record: --force needs on or off"};
            }
            inv.params["force"] = true;
        }
    }

    void settings(const CLI::App& sub, Invocation& inv) const {
        if (sub.count("--dead-zone") > 0) {
            inv.params["dead_zone"] = v_.dead_zone;
        }
        if (sub.count("--follow-speed") > 0) {
            inv.params["follow_speed"] = v_.follow_speed;
        }
        if (sub.count("--inverted") > 0) {
            inv.params["inverted"] =
                v_.inverted == "yes" || v_.inverted == "true" || v_.inverted == "on";
        }
        if (!inv.params.empty()) {
            inv.method = "set_settings";
        }
    }

    Values v_;
    CLI::App app_;
    std::map<std::string, std::string> methods_;
};

}  // namespace

std::optional<std::chrono::milliseconds> parse_duration(std::string_view text) {
    auto ms = args::parse_duration(text);
    return ms && *ms <= kMaxDuration ? ms : std::nullopt;
}

std::string usage(std::string_view command) {
    std::vector<std::string> args = {"--help"};
    if (!command.empty()) {
        args.insert(args.begin(), std::string(command));
    }
    auto parsed = parse_args(args, nullptr);
    return parsed ? parsed->text : usage("");
}

ParseResult parse_args(const std::vector<std::string>& args, const char* env_socket) {
    try {
        return Parser().parse(args, env_socket);
    } catch (UsageError& error) {
        return error;
    }
}

}  // namespace gport::cli
