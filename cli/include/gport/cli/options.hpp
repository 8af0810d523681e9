// gportctl's command line (CLI11): one subcommand per API method, parsed
// into an Invocation without touching the socket, so that it is tested directly.
#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gport/base/exit_status.hpp"
#include "gport/base/result.hpp"
#include "gport/cli/monitor.hpp"
#include "gport/contract/names.hpp"

namespace gport::cli {

// Exit statuses (gport/base/exit_status.hpp).
using gport::kExitOk;
inline constexpr int kExitError = gport::kExitFailure;  // the daemon answered with an error
using gport::kExitInterrupted;
using gport::kExitLinkNotUp;
using gport::kExitNotReached;
using gport::kExitUnavailable;
using gport::kExitUsage;

inline constexpr std::string_view kDefaultSocket = contract::kDefaultSocket;

struct Invocation {
    std::string command;  // subcommand as typed: "status", "watch", "settings", ...
    std::string method;   // the JSON-RPC method it calls
    nlohmann::json params = nlohmann::json::object();
    std::string socket{kDefaultSocket};
    bool json = false;                // --json: raw result objects, one per line
    bool raw = false;                 // call --raw: the whole response
    bool timestamps = false;          // watch --timestamps
    bool help = false;                // --help or --version: print `text` and exit 0
    std::string text;                 // the help page or version asked for
    std::vector<std::string> topics;  // watch
    std::optional<double> rate_hz;    // watch --rate
    bool shared_memory = false;       // watch --shared-memory
    std::optional<long> count;        // watch -n: stop after this many events
    std::optional<std::chrono::milliseconds> duration;  // speed --for, watch --for
    bool wait = false;                                  // angle, center --wait
    MonitorOptions monitor;                             // monitor
    std::uint64_t since = 0;                            // captures --since
    std::optional<long> limit;                          // captures --limit: at most this many
    bool follow = false;                                // captures --follow
    bool csv = false;                                   // captures --csv
    std::optional<std::chrono::milliseconds> timeout;   // wait --timeout (none: forever)
    // geotag DIR (docs/operations.md, "Photos matched to their files")
    std::string geotag_dir;
    std::vector<std::string> captures_files;    // --captures FILE...: not from gportd
    std::chrono::milliseconds tolerance{2000};  // --tolerance
    double clock_offset_s = 0;                  // --clock-offset: camera clock minus UTC
    bool clock_offset_given = false;            // --clock-offset given
    bool force = false;                         // --force: match despite the estimate
    bool in_order = false;                      // --in-order
    bool write = false;                         // --write (else a dry run)
    std::string geo_txt;                        // --geo-txt FILE
};

struct UsageError {
    std::string message;
    std::string command;  // the subcommand it concerns, if any (for "Try 'gportctl X --help'")
};

using ParseResult = Result<Invocation, UsageError>;

// `args` excludes argv[0]. `env_socket` is $GPORT_SOCKET (nullptr if unset);
// --socket wins over it.
ParseResult parse_args(const std::vector<std::string>& args, const char* env_socket);

// "2s", "500ms", "1.5s", "2m" -> milliseconds (1 ms to the protocol's longest).
std::optional<std::chrono::milliseconds> parse_duration(std::string_view text);

// Usage text for one subcommand ("gportctl COMMAND --help"), or the
// overview when `command` is empty.
std::string usage(std::string_view command);

}  // namespace gport::cli
