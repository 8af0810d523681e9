// The JSON codec shared by Client and AsyncClient: request params from the
// typed options, typed results and notifications from gportd's JSON
// (docs/api.md). Decoders throw Error (kBadReply) on a shape they do not
// know; members they do not know are ignored (newer daemons add some).
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gport/client/error.hpp"
#include "gport/client/limits.hpp"
#include "gport/client/types.hpp"

namespace gport::client::codec {

using nlohmann::json;

json speed_params(const Axes& speed, const SpeedOptions& options);
json angle_params(const Axes& target, const AngleOptions& options);
json center_params(const CenterOptions& options);
json record_params(std::optional<bool> on, bool force);
json vehicle_params(const VehicleReport& report);
// Adds options.meta to params as `meta`; the Error (kInvalidParams) when it
// is not the text of a JSON object.
std::optional<Error> add_meta(json& params, const CaptureOptions& options);
json settings_params(const SettingsChange& change);
json subscribe_params(const std::vector<std::string>& topics, std::optional<double> max_rate_hz);
json unsubscribe_params(const std::vector<std::string>& topics);

// How long to wait for the reply to a request with these params: the call
// timeout, plus kWaitAllowance when they ask to "wait" (the reply comes when
// the motion ends); empty: no limit.
std::optional<std::chrono::milliseconds> reply_limit(
    const json& params, std::optional<std::chrono::milliseconds> call_timeout);
// The Error (kTimeout) of a call whose reply did not come within `limit`.
Error no_reply(const std::string& method, std::chrono::milliseconds limit);

// The result of a reply object ({"result":...} or {"error":...}); throws the
// error as Error.
json result_of(const json& reply);

Status status(const json& result);
AttitudeSample attitude(const json& result);
SpeedResult speed_result(const json& result);
AngleResult angle_result(const json& result);
CenterResult center_result(const json& result);
RecordResult record_result(const json& result);
PhotoResult photo_result(const json& result);
PhotoReport photo_report(const json& result);
Control control(const json& result);
Settings settings(const json& result);
Limits limits(const json& result);
Subscription subscription(const json& result);
// captures' params and reply, and a capture notification's params.
json captures_params(std::uint64_t since, std::optional<std::uint32_t> limit);
CapturesPage captures_page(const json& result, std::uint64_t since);
CaptureEntry capture_entry(const json& capture);
CaptureStamp capture_stamp(const json& capture);
// A "capture" notification's entry; empty for any other message.
std::optional<CaptureEntry> capture_notification(const json& message);

// A notification message ({"method":topic,"params":...}); empty for a topic
// this library does not know.
std::optional<Notification> notification(const json& message);

}  // namespace gport::client::codec
