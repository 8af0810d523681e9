// The public decoders of results.hpp: gportd's JSON text parsed once, then
// the codec's decoders, the ones the typed calls use.
#include "gport/client/results.hpp"

#include <string>

#include "codec.hpp"

namespace gport::client {
namespace {

using codec::json;

// The text as JSON, or Error (kBadReply) naming what it was to be.
json parsed(std::string_view text, const char* what) {
    auto value = json::parse(text, nullptr, false);
    if (value.is_discarded()) {
        throw Error(ErrorCode::kBadReply, std::string("a ") + what + " that is not JSON");
    }
    return value;
}

}  // namespace

Status status_from_json(std::string_view result) {
    return codec::status(parsed(result, "status result"));
}

AttitudeSample attitude_from_json(std::string_view result) {
    return codec::attitude(parsed(result, "attitude result"));
}

Settings settings_from_json(std::string_view result) {
    return codec::settings(parsed(result, "settings result"));
}

Limits limits_from_json(std::string_view result) {
    return codec::limits(parsed(result, "limits result"));
}

SpeedResult speed_result_from_json(std::string_view result) {
    return codec::speed_result(parsed(result, "speed result"));
}

AngleResult angle_result_from_json(std::string_view result) {
    return codec::angle_result(parsed(result, "angle result"));
}

CenterResult center_result_from_json(std::string_view result) {
    return codec::center_result(parsed(result, "center result"));
}

PhotoResult photo_result_from_json(std::string_view result) {
    return codec::photo_result(parsed(result, "photo result"));
}

PhotoReport photo_report_from_json(std::string_view result) {
    return codec::photo_report(parsed(result, "photo result"));
}

RecordResult record_result_from_json(std::string_view result) {
    return codec::record_result(parsed(result, "record result"));
}

Subscription subscription_from_json(std::string_view result) {
    return codec::subscription(parsed(result, "subscribe result"));
}

CaptureStamp capture_stamp_from_json(std::string_view capture) {
    return codec::capture_stamp(parsed(capture, "capture"));
}

std::optional<Notification> notification_from_json(std::string_view message) {
    const auto value = parsed(message, "notification");
    if (!value.is_object()) {
        throw Error(ErrorCode::kBadReply, "a notification that is not an object: " + value.dump());
    }
    return codec::notification(value);
}

}  // namespace gport::client
