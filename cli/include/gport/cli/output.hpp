// Human-readable renderings of results and notifications (--json prints the
// raw objects instead).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "gport/client/types.hpp"

namespace gport::cli {

// One result of `command` (a gportctl subcommand), as lines ending in '\n'.
std::string format_result(const std::string& command, const nlohmann::json& result);
// One notification (the whole message) as one line ending in '\n'.
std::string format_notification(const nlohmann::json& message);
// A sample of the shared-memory attitude channel as the attitude
// notification gportd sends on the socket for it (the same JSON values:
// whole numbers as integers, as gportd prints them; "dropped" when some
// samples were missed).
nlohmann::json attitude_notification(const client::AttitudeSample& sample);
// "error -32003: another client holds control (pid 12)"
std::string format_error(const nlohmann::json& error);

}  // namespace gport::cli
