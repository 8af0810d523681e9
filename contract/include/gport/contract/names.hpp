// The names of the client API (docs/api.md): its socket, its methods and the topics a
// client subscribes to (each topic is also the method of its notifications).
// gportd's method table follows kMethods entry by entry (checked where it
// is written, ipc/src/methods.cpp); the Python client's TOPICS are checked
// against kTopics (tests/contract).
//
// Standard C++17.
#pragma once

#include <array>
#include <string_view>

namespace gport::contract {

// Where gportd listens unless told otherwise, and the environment variable
// through which every client (gportctl, gport-mavlink, both libraries) is
// pointed at another socket (docs/api.md, "Transport").
inline constexpr char kDefaultSocket[] = "/run/gportd.sock";
inline constexpr char kSocketEnv[] = "GPORT_SOCKET";

// Each method's name (char arrays: they convert to std::string and
// std::string_view alike), and the table of them in gportd's order.
namespace method {
inline constexpr char kStatus[] = "status";
inline constexpr char kAttitude[] = "attitude";
inline constexpr char kSubscribe[] = "subscribe";
inline constexpr char kUnsubscribe[] = "unsubscribe";
inline constexpr char kAttitudeChannel[] = "attitude_channel";
inline constexpr char kSpeed[] = "speed";
inline constexpr char kStop[] = "stop";
inline constexpr char kAngle[] = "angle";
inline constexpr char kCenter[] = "center";
inline constexpr char kLock[] = "lock";
inline constexpr char kPhoto[] = "photo";
inline constexpr char kRecord[] = "record";
inline constexpr char kCaptures[] = "captures";
inline constexpr char kAcquire[] = "acquire";
inline constexpr char kRelease[] = "release";
inline constexpr char kGetSettings[] = "get_settings";
inline constexpr char kSetSettings[] = "set_settings";
inline constexpr char kLimits[] = "limits";
inline constexpr char kPublishVehicle[] = "publish_vehicle";
}  // namespace method

inline constexpr std::array<std::string_view, 19> kMethods{
    method::kStatus,          method::kAttitude, method::kSubscribe,      method::kUnsubscribe,
    method::kAttitudeChannel, method::kSpeed,    method::kStop,           method::kAngle,
    method::kCenter,          method::kLock,     method::kPhoto,          method::kRecord,
    method::kCaptures,        method::kAcquire,  method::kRelease,        method::kGetSettings,
    method::kSetSettings,     method::kLimits,   method::kPublishVehicle,
};

inline constexpr std::string_view kTopicAttitude = "attitude";
inline constexpr std::string_view kTopicLink = "link";
inline constexpr std::string_view kTopicMotion = "motion";
inline constexpr std::string_view kTopicCapture = "capture";
inline constexpr std::array<std::string_view, 4> kTopics{kTopicAttitude, kTopicLink, kTopicMotion,
                                                         kTopicCapture};

}  // namespace gport::contract
