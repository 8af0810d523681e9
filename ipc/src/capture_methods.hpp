// The camera's methods and the capture log's: photo and record (with their
// optional `meta`, and the capture their reply gains when a toggle reached
// the wire) and captures (docs/api.md, "Captures").
#pragma once

#include <nlohmann/json.hpp>

#include "methods.hpp"

namespace gport::ipc::detail {

void photo(MethodContext& c, const nlohmann::json& params, Respond respond);
void record(MethodContext& c, const nlohmann::json& params, Respond respond);
void captures(MethodContext& c, const nlohmann::json& params, Respond respond);

// The capture as the log keeps it, without its index and kind
// (capture::CaptureLog::add gives them).
nlohmann::json capture_json(const daemon::ClientInfo& client,
                            const std::optional<daemon::AttitudeSample>& attitude,
                            const nlohmann::json* meta);

}  // namespace gport::ipc::detail
