#include "gport/app/reload.hpp"

#include <functional>

namespace gport::app {
namespace {

using config::Config;

struct Key {
    const char* name;
    bool live;  // may change while the daemon runs
    std::function<bool(const Config&, const Config&)> differs;
    std::function<void(Config&, const Config&)> copy;
};

// One key: the member `Field` of the section `Section` of a Config.
template <auto Section, auto Field>
Key key(const char* name, bool live) {
    return Key{
        name, live,
        [](const Config& a, const Config& b) { return (a.*Section).*Field != (b.*Section).*Field; },
        [](Config& to, const Config& from) { (to.*Section).*Field = (from.*Section).*Field; }};
}

const std::vector<Key>& keys() {
    using namespace config;
    static const std::vector<Key> all{
        key<&Config::serial, &SerialConfig::device>("serial.device", false),
        key<&Config::serial, &SerialConfig::baud>("serial.baud", false),
        key<&Config::socket, &SocketConfig::path>("socket.path", false),
        key<&Config::socket, &SocketConfig::mode>("socket.mode", false),
        key<&Config::socket, &SocketConfig::group>("socket.group", false),
        key<&Config::socket, &SocketConfig::line_limit>("socket.line_limit", false),
        key<&Config::socket, &SocketConfig::max_clients>("socket.max_clients", false),
        key<&Config::socket, &SocketConfig::queue_limit>("socket.queue_limit", false),
        // The server keeps the socket section it started with.
        key<&Config::socket, &SocketConfig::max_clients_per_uid>("socket.max_clients_per_uid",
                                                                 false),
        key<&Config::socket, &SocketConfig::reserved_command_slots>("socket.reserved_command_slots",
                                                                    false),
        key<&Config::socket, &SocketConfig::idle_timeout>("socket.idle_timeout_ms", false),
        key<&Config::socket, &SocketConfig::max_requests_per_s>("socket.max_requests_per_s", false),
        key<&Config::keepalive, &KeepaliveConfig::rate_hz>("keepalive.rate_hz", false),
        key<&Config::keepalive, &KeepaliveConfig::default_duration>("keepalive.default_duration_ms",
                                                                    true),
        key<&Config::keepalive, &KeepaliveConfig::max_duration>("keepalive.max_duration_ms", true),
        key<&Config::link, &LinkConfig::stale_after>("link.stale_ms", false),
        key<&Config::link, &LinkConfig::reconnect_initial>("link.reconnect_initial_ms", false),
        key<&Config::link, &LinkConfig::reconnect_max>("link.reconnect_max_ms", false),
        key<&Config::requests, &RequestConfig::timeout>("requests.timeout_ms", false),
        key<&Config::requests, &RequestConfig::retries>("requests.retries", false),
        key<&Config::access, &AccessConfig::control_uids>("access.control_uids", true),
        key<&Config::access, &AccessConfig::control_gids>("access.control_gids", true),
        key<&Config::access, &AccessConfig::vehicle_uids>("access.vehicle_uids", true),
        key<&Config::log, &LogConfig::level>("log.level", true),
        key<&Config::realtime, &RealtimeConfig::priority>("realtime.priority", false),
        key<&Config::realtime, &RealtimeConfig::lock_memory>("realtime.lock_memory", false),
        key<&Config::limits, &LimitsConfig::roll>("limits.roll", true),
        key<&Config::limits, &LimitsConfig::pitch>("limits.pitch", true),
        key<&Config::limits, &LimitsConfig::yaw>("limits.yaw", true),
        key<&Config::limits, &LimitsConfig::max_speed>("limits.max_speed", true),
        key<&Config::limits, &LimitsConfig::braking_margin_deg>("limits.braking_margin_deg", true),
        key<&Config::failsafe, &FailsafeConfig::on_owner_gone>("failsafe.on_owner_gone", true),
        key<&Config::failsafe, &FailsafeConfig::on_shutdown>("failsafe.on_shutdown", true),
        key<&Config::failsafe, &FailsafeConfig::on_link_lost>("failsafe.on_link_lost", true),
        key<&Config::motion, &MotionConfig::tolerance_deg>("motion.tolerance_deg", true),
        key<&Config::motion, &MotionConfig::timeout>("motion.timeout_ms", true),
        key<&Config::motion, &MotionConfig::stall>("motion.stall_ms", true),
        // Core::reload hands it to the camera limit's token bucket.
        key<&Config::camera, &CameraConfig::max_commands_per_s>("camera.max_commands_per_s", true),
        // Read by Core for each capture's stamp.
        key<&Config::camera, &CameraConfig::shutter_delay>("camera.shutter_delay_ms", true),
        key<&Config::camera, &CameraConfig::max_position_age>("camera.max_position_age_ms", true),
        // The writer thread holds its file open: a new place or rotation needs a restart.
        key<&Config::captures, &CapturesConfig::dir>("captures.dir", false),
        key<&Config::captures, &CapturesConfig::max_file_bytes>("captures.max_file_bytes", false),
        key<&Config::captures, &CapturesConfig::keep_files>("captures.keep_files", false),
    };
    return all;
}

}  // namespace

ReloadPlan plan_reload(const Config& running, const Config& next) {
    ReloadPlan plan{running, {}, {}};
    for (const auto& k : keys()) {
        if (!k.differs(running, next)) {
            continue;
        }
        if (k.live) {
            k.copy(plan.in_effect, next);
            plan.applied.emplace_back(k.name);
        } else {
            plan.need_restart.emplace_back(k.name);
        }
    }
    return plan;
}

}  // namespace gport::app
