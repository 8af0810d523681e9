// The names of the client API (docs/api.md): its methods and the topics a
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

inline constexpr std::array<std::string_view, 18> kMethods{
    "status",       "attitude",     "subscribe", "unsubscribe", "attitude_channel",
    "speed",        "stop",         "angle",     "center",      "lock",
    "photo",        "record",       "captures",  "acquire",     "release",
    "get_settings", "set_settings", "limits",
};

inline constexpr std::string_view kTopicAttitude = "attitude";
inline constexpr std::string_view kTopicLink = "link";
inline constexpr std::string_view kTopicMotion = "motion";
inline constexpr std::string_view kTopicCapture = "capture";
inline constexpr std::array<std::string_view, 4> kTopics{kTopicAttitude, kTopicLink, kTopicMotion,
                                                         kTopicCapture};

}  // namespace gport::contract
