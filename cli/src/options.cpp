// gportctl's command line on CLI11: global options anywhere, one subcommand,
// its options. Values are checked here against the wire contract's ranges,
// so that a typo is a usage error (64) before any connection is made.
#include "gport/cli/options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <tuple>

#include "geotag.hpp"
#include "gport/base/args.hpp"
#include "gport/client/client.hpp"
#include "gport/contract/limits.hpp"
#include "gport/contract/names.hpp"
#include "suggest.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

// The longest --for and --lease gportctl sends; gportd's own
// keepalive.max_duration_ms is lower (run.cpp reports its refusal as a
// usage error naming the option).
constexpr std::chrono::milliseconds kMaxDuration{contract::kMaxDurationMs};
// wait --timeout: a day at most (a unit's start-up, a vehicle's power-on).
constexpr std::chrono::milliseconds kMaxWait = std::chrono::hours(24);

// call: the longest method name, and the deepest params, gportctl sends.
constexpr std::size_t kMaxMethodLength = 64;
constexpr int kMaxParamsDepth = 32;

constexpr const char* kDescription =
    "Talks to gportd, the G-Port gimbal daemon, over its Unix socket.";

// The overview's footer, after "Usage" and the commands.
constexpr const char* kOverviewFooter =
    "acquire and release are not commands: control held by a one-shot process\n"
    "would be released the moment it exits. A program that needs exclusive\n"
    "control keeps its own connection and calls \"acquire\" (see docs/api.md).\n\n"
    "Exit status: 0 success, 1 the daemon refused (message and code on stderr),\n"
    "2 angle/center --wait ended without reaching the target, 64 usage error,\n"
    "69 daemon unreachable, 75 the gimbal's link is not up (status; wait link\n"
    "timed out), 130 interrupted (Ctrl-C, SIGTERM).";

// Every command's footer: the options that apply everywhere, and where the
// exit statuses are.
constexpr const char* kCommandFooter =
    "Global options (before or after the command): --socket PATH, --json,\n"
    "-h/--help, --version. Exit statuses: gportctl --help.\n";

// The options that apply before the command.
const std::vector<std::string> kGlobalOptions = {"--socket", "--json", "--help", "--version"};

const std::vector<std::string> kTopics = {std::string(contract::kTopicAttitude),
                                          std::string(contract::kTopicLink),
                                          std::string(contract::kTopicMotion)};

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
    std::string call_method, call_params;  // call
    bool raw = false;
    bool timestamps = false;    // watch
    long since = 0, limit = 0;  // captures
    bool follow = false, csv = false;
    std::string wait_for, timeout_text;  // wait
    double lat = 0, lon = 0, alt = 0;    // photo, record
    std::string meta;
    std::string geotag_dir, tolerance_text = "2s", geo_txt;  // geotag
    std::vector<std::string> captures_files;
    double clock_offset = 0;
    bool in_order = false, write = false;
};

// The command word in `args` (the first argument that is not an option or
// the value of --socket), and its index; nullopt when there is none.
std::optional<std::pair<std::size_t, std::string>> command_word(
    const std::vector<std::string>& args) {
    for (std::size_t i = 0; i < args.size(); ++i) {
        if (args[i] == "--socket") {
            ++i;
        } else if (!args[i].starts_with("-") || args[i] == "-") {
            return std::pair{i, args[i]};
        }
    }
    return std::nullopt;
}

// "--yaw=5" -> "--yaw".
std::string option_name(const std::string& token) {
    return token.substr(0, token.find('='));
}

class Parser {
  public:
    Parser() : app_(kDescription, "gportctl") {
        args::configure(app_, kOverviewFooter);
        app_.require_subcommand(0, 1);
        app_.allow_extras();  // checked after parsing, to name the command
        app_.add_option("--socket", v_.socket,
                        fmt::format("daemon socket (default {}, or $GPORT_SOCKET)", kDefaultSocket))
            ->type_name("PATH");
        app_.add_flag("--json", v_.json, "print raw JSON result objects, one per line");
        add_commands();
    }

    Invocation parse(const std::vector<std::string>& args, const char* env_socket) {
        args_ = args;
        std::vector<std::string> reversed(args.rbegin(), args.rend());
        try {
            app_.parse(reversed);
        } catch (const CLI::ParseError& error) {
            if (!args::is_request(error)) {
                throw UsageError{args::message_of(error), known_command()};
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
        sub->footer(kCommandFooter);
        methods_[name] = method;
        return sub;
    }

    // A command's own notes, then the footer every command has.
    static void footer(CLI::App* sub, const std::string& notes) {
        sub->footer(notes + "\n" + kCommandFooter);
    }

    // The command typed, if it is one of ours (for the usage hint).
    std::string known_command() const {
        const auto word = command_word(args_);
        return word && methods_.contains(word->second) ? word->second : std::string();
    }

    std::vector<std::string> command_names() const {
        std::vector<std::string> names;
        for (const auto* sub : app_.get_subcommands({})) {
            names.push_back(sub->get_name());
        }
        return names;
    }

    static std::vector<std::string> option_names(const CLI::App* sub) {
        std::vector<std::string> names;
        for (const auto* option : sub->get_options()) {
            if (option->get_name() != "--help" && !option->get_lnames().empty()) {
                names.push_back(option->get_name());
            }
        }
        return names;
    }

    void add_axes(CLI::App* sub, std::string_view unit) {
        const auto range =
            args::number_in(-contract::kMaxDegrees, contract::kMaxDegrees, std::string(unit));
        for (auto [name, value] : {std::pair{"roll", &v_.roll}, std::pair{"pitch", &v_.pitch},
                                   std::pair{"yaw", &v_.yaw}}) {
            sub->add_option(fmt::format("--{}", name), *value, fmt::format("{} ({})", name, unit))
                ->type_name(unit == std::string_view("degrees") ? "DEG" : "DEG/S")
                ->check(range);
        }
        sub->add_flag("--clamp", v_.clamp,
                      unit == std::string_view("degrees")
                          ? "clamp the target into gportd's soft limits instead of refusing"
                          : "slow to gportd's limits.max_speed instead of refusing");
    }

    void add_commands() {
        add_status();
        command("attitude", contract::method::kAttitude, "the latest attitude sample");
        add_watch();
        add_speed();
        command("stop", contract::method::kStop, "stop any motion now");
        add_angle();
        command("center", contract::method::kCenter, "centre the gimbal")
            ->add_flag("--wait", v_.wait, "wait until centred; exit 2 if it is not");
        command("lock", contract::method::kLock, "lock mode (control mode 4)");
        add_photo();
        add_record();
        add_settings();
        add_monitor();
        add_call();
        add_captures();
        add_geotag_dir();
        add_wait();
        command("limits", contract::method::kLimits,
                "the soft limits gportd enforces (angles, max speed)");
        auto* help = command("help", "", "this text, or a command's");
        help->add_option("command", v_.help_topic, "the command to describe");
    }

    void add_status() {
        auto* sub = command("status", contract::method::kStatus,
                            "link, device, counters, clients, current motion");
        footer(sub,
               "A health check: exits 75 while the gimbal's link is not up (down or\n"
               "stale), after printing the status as ever; 0 when it is up. To wait\n"
               "for it instead: gportctl wait link.\n");
    }

    void add_wait() {
        auto* sub = command("wait", "", "wait until the gimbal's link is up (for scripts, units)");
        sub->add_option("what", v_.wait_for, "what to wait for: link")
            ->required()
            ->check(args::one_of({"link"}));
        sub->add_option("--timeout", v_.timeout_text, "give up after DURATION (default: never)")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, kMaxWait));
        footer(sub,
               "Exits 0 and prints the link's state once it is up (at once if it is).\n"
               "It follows gportd's link events, no polling. After --timeout it exits\n"
               "75 naming what it waited for and the link's last state; Ctrl-C exits\n"
               "130, a daemon that cannot be reached 69. In a unit:\n"
               "  ExecStartPre=/usr/bin/gportctl wait link --timeout 1m\n");
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

    void add_call() {
        auto* sub = command("call", "", "call any API method; print its result as JSON");
        sub->add_option("method", v_.call_method, "the method (docs/api.md), e.g. limits")
            ->type_name("METHOD");
        sub->add_option("params", v_.call_params, "its params: a JSON object or array")
            ->type_name("PARAMS-JSON");
        sub->add_flag("--raw", v_.raw, "print the whole response (id, result or error)");
        footer(sub,
               "Sends one request and prints the result on one line of JSON, for the\n"
               "methods gportctl has no command for and for scripts. An error is printed\n"
               "on stderr as by every command (exit 1). --raw prints the whole response\n"
               "instead of the result, a refusal's too. The connection closes on exit, so\n"
               "what a method holds (acquire, subscribe) ends with it. Example:\n"
               "  gportctl call angle '{\"pitch\": -30, \"wait\": true}'\n");
    }

    void add_captures() {
        auto* sub = command("captures", contract::method::kCaptures,
                            "the capture log: photos and record toggles with their attitude");
        sub->add_option("--since", v_.since, "from capture INDEX on (default: the oldest kept)")
            ->type_name("INDEX")
            ->check(args::integer_in(0, std::numeric_limits<long>::max()));
        sub->add_option("--limit", v_.limit, "at most COUNT captures (default: all kept)")
            ->type_name("COUNT")
            ->check(args::integer_in(1, std::numeric_limits<long>::max()));
        sub->add_flag("--follow", v_.follow, "then print each new capture until Ctrl-C");
        sub->add_flag("--csv", v_.csv,
                      "CSV with a header: index,utc,kind,imu_*,hall_*,lat,lon,alt_m");
        footer(sub,
               "Prints the captures gportd keeps (the newest 4096), oldest first: a\n"
               "table, CSV for geotagging (utc in ISO 8601 UTC; lat, lon and alt_m from\n"
               "the capture's meta, empty when it has none), or with --json one capture\n"
               "object per line. --follow goes on with each new capture (the capture\n"
               "topic) until Ctrl-C; --limit then counts only the captures listed first.\n");
    }

    void add_geotag_dir() {
        auto* sub = command("geotag", "",
                            "write each photo's position and gimbal angles into its image file");
        sub->add_option("dir", v_.geotag_dir, "the folder of the camera's JPEG files")
            ->required()
            ->type_name("DIR");
        sub->add_option("--captures", v_.captures_files,
                        "read the captures from these capture log files (captures.jsonl*) "
                        "instead of gportd")
            ->type_name("FILE...");
        sub->add_option("--since", v_.since, "only captures from INDEX on (default: all)")
            ->type_name("INDEX")
            ->check(args::integer_in(0, std::numeric_limits<long>::max()));
        sub->add_option("--tolerance", v_.tolerance_text,
                        "match an image to a capture at most DURATION apart (default 2s)")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, 3600s));
        sub->add_option("--clock-offset", v_.clock_offset,
                        "the camera's clock minus UTC in seconds, when its images carry no "
                        "OffsetTimeOriginal (3600: a camera set to UTC+1; default 0)")
            ->type_name("SECONDS")
            ->check(args::number_in(-86400, 86400, "seconds"));
        sub->add_flag("--in-order", v_.in_order,
                      "match the images, oldest first, to the photos in index order instead "
                      "of by time");
        sub->add_flag("--write", v_.write, "write the tags (default: a dry run that only reports)");
        sub->add_flag("--force", v_.force,
                      "match at --clock-offset even when the images pair better at another "
                      "offset, or as well at two");
        sub->add_option("--geo-txt", v_.geo_txt,
                        "also write OpenDroneMap's image geolocation file (geo.txt) here")
            ->type_name("FILE");
        footer(sub,
               "Matches the JPEG files in DIR to gportd's photo captures, closest in time\n"
               "first (the camera's DateTimeOriginal; --in-order when its clock is not\n"
               "set), prints what matched and what did not, and with --write writes each\n"
               "capture's position (EXIF GPS) and the gimbal's pitch and roll (and yaw\n"
               "when the meta has heading_deg; XMP drone-dji Gimbal*Degree) with exiftool\n"
               "(libimage-exiftool-perl), which keeps every original as NAME_original.\n"
               "\n"
               "By time, it first estimates the camera's clock from the data: the offset\n"
               "within --tolerance that pairs the most images with captures within 0.5 s.\n"
               "It refuses to match (nothing written, exit 1) when that offset is more\n"
               "than 1 s from --clock-offset (the message names it: pass it as\n"
               "--clock-offset) or when another offset, over 1 s away, pairs as many\n"
               "images (ambiguous), unless --force. --in-order refuses images without a\n"
               "DateTimeOriginal and a number of images other than of captures.\n"
               "\n"
               "Exits 0 when every image matched a capture with a position (and, with\n"
               "--write, was written); 1 when one did not (each named), or refused.\n");
    }

    void add_watch() {
        auto* sub = command("watch", contract::method::kSubscribe,
                            "stream attitude, link and motion events");
        sub->add_option("topics", v_.topics, "attitude, link, motion (default: all three)")
            ->check(args::one_of(kTopics));
        sub->add_option("--rate", v_.rate, "at most HZ attitude samples a second (the newest)")
            ->type_name("HZ")
            ->check(args::number_in(contract::kMinRateHz, contract::kMaxRateHz, "a rate in Hz"));
        sub->add_flag("--shared-memory", v_.shared_memory,
                      "attitude from gportd's shared-memory channel (every sample)");
        sub->add_option("-n,--count", v_.count, "exit 0 after COUNT events")
            ->type_name("COUNT")
            ->check(args::integer_in(1, std::numeric_limits<int>::max()));
        sub->add_option("--for", v_.for_text, "exit 0 after DURATION (2s, 500ms, 1m)")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, kMaxDuration));
        sub->add_flag("--timestamps", v_.timestamps,
                      "begin each line with the local time it was printed (ISO 8601)");
        footer(sub,
               "Prints each event as it arrives until Ctrl-C (exit 0), COUNT events or\n"
               "DURATION. --rate limits attitude, always delivering the newest sample.\n"
               "--shared-memory reads attitude from the shared-memory channel instead of\n"
               "the socket (every sample, the same output; not with --rate). What is\n"
               "watched is said on stderr when it is a terminal. --timestamps: such as\n"
               "2026-05-04T13:02:07.250+02:00 (not with --json, whose attitude has t).\n");
    }

    void add_speed() {
        auto* sub = command("speed", contract::method::kSpeed,
                            "move at a speed (until Ctrl-C, or --for DURATION)");
        add_axes(sub, "deg/s");
        sub->add_option("--for", v_.for_text, "the daemon keeps the motion going this long")
            ->type_name("DURATION")
            ->check(args::duration_in(1ms, kMaxDuration));
        sub->add_option("--lease", v_.lease_text,
                        "the daemon ends the motion when no speed arrives within it")
            ->type_name("MS")
            ->check(args::duration_in(1ms, kMaxDuration, true));
        footer(sub,
               "Axes not given are 0. A speed above gportd's limits.max_speed is refused,\n"
               "or with --clamp slowed to it. Without --for the motion lasts until Ctrl-C or\n"
               "SIGTERM: gportctl re-sends the speed every 200 ms for 500 ms at a time (if\n"
               "gportctl dies, the gimbal stops within half a second), then sends stop.\n"
               "With --for the daemon keeps the motion going and gportctl shows its progress\n"
               "until it ends; Ctrl-C stops it early. A --for or --lease longer than gportd's\n"
               "keepalive.max_duration_ms is a usage error (64) naming the daemon's limit.\n");
    }

    void add_angle() {
        auto* sub = command("angle", contract::method::kAngle,
                            "go to an angle (--wait: until it is reached)");
        add_axes(sub, "degrees");
        sub->add_flag("--wait", v_.wait, "wait for the end; print it; exit 2 unless reached");
        footer(sub,
               "Angle control relative to the aircraft; axes not given are 0. A target\n"
               "beyond gportd's soft limits is refused, or with --clamp clamped into them.\n"
               "--wait prints how the motion ended (reached, stalled, timeout, replaced,\n"
               "stop, ...), where a stalled gimbal stopped, and the attitude reached.\n"
               "Ctrl-C while waiting exits 130 and the daemon\n"
               "applies its failsafe. Without --wait the gimbal goes on after gportctl exits.\n");
    }

    // photo and record: the capture's position and meta.
    void add_geotag(CLI::App* sub) {
        sub->add_option("--lat", v_.lat, "latitude of the capture (degrees, WGS 84)")
            ->type_name("DEG")
            ->check(args::number_in(-90, 90, "degrees of latitude"));
        sub->add_option("--lon", v_.lon, "longitude of the capture (degrees, WGS 84)")
            ->type_name("DEG")
            ->check(args::number_in(-180, 180, "degrees of longitude"));
        sub->add_option("--alt", v_.alt, "altitude (metres; meta's alt_m)")
            ->type_name("M")
            ->check(args::number_in(-100000, 100000, "metres"));
        sub->add_option("--meta", v_.meta, "more of the capture's meta: a JSON object")
            ->type_name("JSON");
    }

    static constexpr const char* kGeotagNotes =
        "--lat and --lon (with --alt, optional) go into the capture's meta as lat,\n"
        "lon and alt_m, the columns of the capture log's CSV; --meta adds a JSON\n"
        "object of your own (at most 1024 bytes; a key an option sets too is an\n"
        "error). Prints the capture's index; --json prints gportd's result.\n";

    void add_photo() {
        auto* sub =
            command("photo", contract::method::kPhoto, "take a photo (--lat/--lon: geotag it)");
        add_geotag(sub);
        footer(sub, std::string(kGeotagNotes) +
                        "Example: gportctl photo --lat 47.397742 --lon 8.545594 --alt 488.5\n");
    }

    void add_record() {
        auto* sub = command("record", contract::method::kRecord,
                            "toggle recording, or switch it on or off");
        add_geotag(sub);
        sub->add_option("state", v_.state, "on or off (default: toggle)")
            ->check(args::one_of({"on", "off"}));
        sub->add_flag("--force", v_.force, "toggle even when the state is unknown");
        footer(sub,
               "The gimbal never reports whether it records: gportd assumes a state from\n"
               "the toggles it sent, unknown at start and whenever the device reopens.\n"
               "on and off toggle only when the assumed state differs; while it is unknown\n"
               "they are refused unless --force.\n" +
                   std::string(kGeotagNotes));
    }

    void add_settings() {
        auto* sub = command("settings", contract::method::kGetSettings,
                            "read the settings, or change some");
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
            throw UsageError{first.starts_with("-")
                                 ? global_problem(option_name(first), nullptr)
                                 : fmt::format("unknown command \"{}\"{}", first,
                                               did_you_mean(first, command_names(), true)),
                             {}};
        }
        const std::string name = sub->get_name();
        if (!first.starts_with("-")) {
            throw UsageError{fmt::format("{}: unexpected argument \"{}\"", name, first), name};
        }
        const auto option = option_name(first);
        if (before_command(option)) {
            const bool its_own = sub->get_option_no_throw(option) != nullptr;
            throw UsageError{global_problem(option, sub), its_own ? name : std::string()};
        }
        const auto names = option_names(sub);
        auto candidates = names;
        candidates.insert(candidates.end(), kGlobalOptions.begin(), kGlobalOptions.end());
        throw UsageError{
            fmt::format("{}: unknown option {}{}{}", name, option,
                        names.empty() ? "; it takes none"
                                      : "; options: " + fmt::format("{}", fmt::join(names, ", ")),
                        did_you_mean(option, candidates, false)),
            name};
    }

    // Whether `option` was typed before the command word.
    bool before_command(const std::string& option) const {
        const auto word = command_word(args_);
        for (std::size_t i = 0; i < args_.size() && (!word || i < word->first); ++i) {
            if (option_name(args_[i]) == option) {
                return true;
            }
        }
        return false;
    }

    // An unknown option before the command: one of the command's own (in the
    // wrong place), or no option at all.
    std::string global_problem(const std::string& option, const CLI::App* sub) const {
        if (sub != nullptr && sub->get_option_no_throw(option) != nullptr) {
            return fmt::format(
                "{} is an option of {}, not a global one: put it after the command "
                "(gportctl {} {} ...)",
                option, sub->get_name(), sub->get_name(), option);
        }
        return fmt::format("unknown option {}; the global options are {}{}", option,
                           fmt::join(kGlobalOptions, ", "),
                           did_you_mean(option, kGlobalOptions, false));
    }

    Invocation build(const char* env_socket) {
        const auto subs = app_.get_subcommands();
        const CLI::App* sub = subs.empty() ? nullptr : subs.front();
        check_extras(sub);
        if (sub == nullptr) {
            throw UsageError{"no command given", {}};
        }
        Invocation inv;
        inv.command = sub->get_name();
        inv.method = methods_.at(inv.command);
        inv.json = v_.json;
        if (inv.command == "call") {
            call(inv);
        }
        inv.socket =
            app_.count("--socket") > 0 ? v_.socket : client::Client::default_socket(env_socket);
        if (inv.command == "help") {
            return help_of(v_.help_topic);
        }
        if (inv.command == "watch") {
            watch(inv.json, *sub, inv);
        } else if (inv.command == "speed" || inv.command == "angle" || inv.command == "center") {
            motion(*sub, inv);
        } else if (inv.command == "record") {
            record(*sub, inv);
            geotag(*sub, inv);
        } else if (inv.command == "photo") {
            geotag(*sub, inv);
        } else if (inv.command == "settings") {
            settings(*sub, inv);
        } else if (inv.command == "monitor") {
            monitor(*sub, inv);
        } else if (inv.command == "captures") {
            captures(inv);
        } else if (inv.command == "geotag") {
            geotag_dir(*sub, inv);
        } else if (inv.command == "wait" && sub->count("--timeout") > 0) {
            inv.timeout = args::parse_duration(v_.timeout_text);
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
            throw UsageError{fmt::format("help: unknown command \"{}\"{}", topic,
                                         did_you_mean(topic, command_names(), true)),
                             "help"};
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

    // call METHOD [PARAMS-JSON]: the method a name, the params an object or
    // array (JSON-RPC's), nested no deeper than gportd reads.
    void call(Invocation& inv) const {
        const auto& method = v_.call_method;
        if (method.empty()) {
            throw UsageError{
                "call: no METHOD given; expected METHOD [PARAMS-JSON], such as "
                "gportctl call limits",
                "call"};
        }
        if (method.empty() || method.size() > kMaxMethodLength ||
            method.find_first_not_of("abcdefghijklmnopqrstuvwxyz"
                                     "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.") !=
                std::string::npos) {
            throw UsageError{fmt::format("call: METHOD \"{}\": expected a method name (letters, "
                                         "digits, _ and ., at most {}), such as limits",
                                         method.substr(0, kMaxMethodLength), kMaxMethodLength),
                             "call"};
        }
        inv.method = method;
        inv.raw = v_.raw;
        if (v_.call_params.empty()) {
            return;
        }
        bool too_deep = false;
        auto params = json::parse(
            v_.call_params,
            [&too_deep](int depth, json::parse_event_t, json&) {
                too_deep = too_deep || depth > kMaxParamsDepth;
                return !too_deep;
            },
            false);
        if (too_deep) {
            throw UsageError{
                fmt::format("call: PARAMS-JSON nests deeper than {} levels", kMaxParamsDepth),
                "call"};
        }
        if (!params.is_object() && !params.is_array()) {
            throw UsageError{
                fmt::format("call: PARAMS-JSON {}: expected a JSON object or array, such as "
                            "'{{\"pitch\": -30}}'",
                            params.is_discarded() ? "is not valid JSON"
                                                  : "is a " + std::string(params.type_name())),
                "call"};
        }
        inv.params = std::move(params);
    }

    void watch(bool json_output, const CLI::App& sub, Invocation& inv) const {
        if (v_.timestamps && json_output) {
            throw UsageError{
                "watch: --timestamps and --json cannot be combined (--json prints gportd's "
                "objects unchanged; attitude has t, the time gportd received it)",
                "watch"};
        }
        inv.timestamps = v_.timestamps;
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
                    "channel offers every sample)",
                    "watch"};
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

    void geotag_dir(const CLI::App& sub, Invocation& inv) const {
        inv.geotag_dir = v_.geotag_dir;
        inv.clock_offset_given = sub.count("--clock-offset") > 0;
        inv.force = v_.force;
        inv.captures_files = v_.captures_files;
        inv.since = static_cast<std::uint64_t>(v_.since);
        inv.tolerance = *args::parse_duration(v_.tolerance_text);
        inv.clock_offset_s = v_.clock_offset;
        inv.in_order = v_.in_order;
        inv.write = v_.write;
        inv.geo_txt = v_.geo_txt;
    }

    void captures(Invocation& inv) const {
        if (v_.csv && inv.json) {
            throw UsageError{
                "captures: --csv and --json cannot be combined (--json prints gportd's capture "
                "objects, --csv a table of them)",
                "captures"};
        }
        inv.since = static_cast<std::uint64_t>(v_.since);
        if (v_.limit > 0) {
            inv.limit = v_.limit;
        }
        inv.follow = v_.follow;
        inv.csv = v_.csv;
    }

    void geotag(const CLI::App& sub, Invocation& inv) const {
        GeotagArgs args;
        const auto given = [&sub](const char* name) { return sub.count(name) > 0; };
        for (const auto& [name, from, to] :
             {std::tuple{"--lat", &v_.lat, &args.lat}, std::tuple{"--lon", &v_.lon, &args.lon},
              std::tuple{"--alt", &v_.alt, &args.alt}}) {
            if (given(name)) {
                *to = *from;
            }
        }
        if (given("--meta")) {
            args.meta = v_.meta;
        }
        auto meta = geotag_meta(args);
        if (!meta) {
            throw UsageError{fmt::format("{}: {}", inv.command, meta.error()), inv.command};
        }
        if (*meta) {
            inv.params["meta"] = std::move(**meta);
        }
    }

    void record(const CLI::App& sub, Invocation& inv) const {
        if (sub.count("state") > 0) {
            inv.params["on"] = v_.state == "on";
        }
        if (v_.force) {
            if (sub.count("state") == 0) {
                throw UsageError{"record: --force needs on or off", "record"};
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
            inv.method = contract::method::kSetSettings;
        }
    }

    Values v_;
    std::vector<std::string> args_;
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
