// The low JSON pieces shared by results (result_json) and notifications
// (event_json). Both include this; neither includes the other.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "gport/daemon/api.hpp"

namespace gport::ipc::detail {

// One message as an NDJSON line: compact, invalid UTF-8 replaced, newline-ended.
std::string json_line(const nlohmann::json& message);
// The same without the newline (invalid UTF-8 replaced, as json_line does).
std::string json_text(const nlohmann::json& value);

nlohmann::json client_json(const daemon::ClientInfo& client);
nlohmann::json axes_json(const protocol::Axes& axes);  // degrees from 0.01 units
double epoch_seconds(daemon::WallTime time);           // with microsecond resolution

}  // namespace gport::ipc::detail
