#include "json_common.hpp"

#include <fmt/format.h>

#include <chrono>

namespace gport::ipc::detail {

std::string json_line(const nlohmann::json& message) {
    return json_text(message) + '\n';
}

std::string json_text(const nlohmann::json& value) {
    return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json client_json(const daemon::ClientInfo& client) {
    return {{"id", client.id}, {"pid", client.pid}, {"uid", client.uid}, {"gid", client.gid}};
}

nlohmann::json axes_json(const protocol::Axes& axes) {
    const auto [roll, pitch, yaw] = protocol::degrees_of(axes);
    return {{"roll", roll}, {"pitch", pitch}, {"yaw", yaw}};
}

double epoch_seconds(daemon::WallTime time) {
    const auto us =
        std::chrono::duration_cast<std::chrono::microseconds>(time.time_since_epoch()).count();
    if (us < 0) {
        return static_cast<double>(us) / 1e6;
    }
    // Through text, so that the double is the one nearest to the printed
    // microseconds and prints back the same way.
    return std::stod(fmt::format("{}.{:06}", us / 1'000'000, us % 1'000'000));
}

}  // namespace gport::ipc::detail
