// Human-readable renderings of results and notifications (--json prints the
// raw objects instead).
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "gport/client/error.hpp"

namespace gport::cli {

// One result of `command` (a gportctl subcommand), as lines ending in '\n'.
std::string format_result(const std::string& command, const nlohmann::json& result);
// One notification (the whole message) as one line ending in '\n'.
std::string format_notification(const nlohmann::json& message);
// The one format of a daemon's error: "error -32003: another client holds
// control (pid 12)".
std::string format_error(const nlohmann::json& error);
// A client library error: a refusal as above; the connection's own
// problems (cannot connect, timeout, bad reply) as the library words them.
std::string format_error(const client::Error& error);
// A refusal worded for the command line: the API's params the message
// suggests become gportctl's options (`record {"on": true, "force": true}`
// -> `gportctl record on --force`, `clamp: true` -> `--clamp`).
nlohmann::json cli_wording(const nlohmann::json& error);
// "2026-05-04T13:02:07.250+02:00": local time, milliseconds, the offset.
std::string format_timestamp(std::chrono::system_clock::time_point when);

}  // namespace gport::cli
