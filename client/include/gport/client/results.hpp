// gportd's results and notifications, typed, from their JSON text: the
// decoders the typed calls of Client and AsyncClient use, for a program that
// holds the text (Client::call_json, AsyncClient::async_call_json,
// on_notification_json) and wants fields by type rather than by name, as
// gportctl prints them (1.7.0).
//
// Each *_from_json takes a method's `result` (an object) and returns what
// the typed call of that method returns, decoded as that call decodes it:
// members it does not know are ignored (newer daemons add some), and it
// throws Error (kBadReply), naming the result and what did not decode, when
// the text is not JSON, not an object, or lacks or mistypes a member the
// type needs.
#pragma once

#include <optional>
#include <string_view>

#include "gport/client/error.hpp"
#include "gport/client/export.hpp"
#include "gport/client/types.hpp"

namespace gport::client {

GPORT_CLIENT_API Status status_from_json(std::string_view result);
GPORT_CLIENT_API AttitudeSample attitude_from_json(std::string_view result);
GPORT_CLIENT_API Settings settings_from_json(std::string_view result);
GPORT_CLIENT_API Limits limits_from_json(std::string_view result);
GPORT_CLIENT_API SpeedResult speed_result_from_json(std::string_view result);
GPORT_CLIENT_API AngleResult angle_result_from_json(std::string_view result);
GPORT_CLIENT_API CenterResult center_result_from_json(std::string_view result);
GPORT_CLIENT_API PhotoResult photo_result_from_json(std::string_view result);
// photo's result as async_photo_report decodes it: the capture and its
// attitude (1.10.0).
GPORT_CLIENT_API PhotoReport photo_report_from_json(std::string_view result);
GPORT_CLIENT_API RecordResult record_result_from_json(std::string_view result);
GPORT_CLIENT_API Subscription subscription_from_json(std::string_view result);
// One capture object (a captures page's entry, the capture topic's params,
// a line of captures.jsonl), or a photo or record result holding one as
// "capture": its moment and vehicle (1.10.0). Members it lacks stay empty; a vehicle
// that is neither null nor an object with "tagged" throws kBadReply.
GPORT_CLIENT_API CaptureStamp capture_stamp_from_json(std::string_view capture);

// A whole notification line ({"method": topic, "params": ...}); empty for a
// topic this library has no type for (capture, and topics newer daemons
// add). Throws like the above when its params do not decode.
GPORT_CLIENT_API std::optional<Notification> notification_from_json(std::string_view message);

}  // namespace gport::client
