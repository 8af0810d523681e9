#include "gport/mavlink/bridge/trust.hpp"

#include "gport/mavlink/enums.hpp"

namespace gport::mavlink::bridge {

Concern concern_of(std::uint32_t msgid) {
    switch (msgid) {
        case GimbalDeviceSetAttitude::kId:
        case CommandLong::kId:
            return Concern::kCommand;
        case Heartbeat::kId:
        case AutopilotStateForGimbalDevice::kId:
        case Attitude::kId:
        case GlobalPositionInt::kId:
        case GpsRawInt::kId:
        case SystemTime::kId:
            return Concern::kVehicleState;
        default:
            return Concern::kOther;
    }
}

std::string_view to_string(TrustVerdict verdict) {
    switch (verdict) {
        case TrustVerdict::kTrusted:
            return "trusted";
        case TrustVerdict::kNoVehicle:
            return "no vehicle adopted yet";
        case TrustVerdict::kNotVehicle:
            return "a ground station, not the vehicle";
        case TrustVerdict::kStranger:
            return "neither the vehicle nor a ground station";
        case TrustVerdict::kOwnEcho:
            return "our own frame, sent back";
    }
    return "unknown";
}

bool is_autopilot(const Heartbeat& heartbeat) {
    return heartbeat.type != mav_type::kGcs && heartbeat.autopilot != mav_autopilot::kInvalid;
}

Trust::Trust(const TrustPolicy& policy)
    : vehicle_(policy.vehicle),
      adopts_(!policy.vehicle.has_value()),
      ground_stations_(policy.ground_stations),
      own_components_(policy.own_components) {
    ground_stations_.reset(0);  // 0 is the broadcast id, never a sender's
}

bool Trust::on_heartbeat(const Header& from, const Heartbeat& heartbeat) {
    if (!adopts_ || vehicle_ || from.sysid == 0 || !is_autopilot(heartbeat)) {
        return false;
    }
    vehicle_ = from.sysid;
    return true;
}

TrustVerdict Trust::judge(const Header& from, Concern concern) const {
    if (!vehicle_) {
        return TrustVerdict::kNoVehicle;
    }
    if (from.sysid == *vehicle_) {
        return own_components_.test(from.compid) ? TrustVerdict::kOwnEcho : TrustVerdict::kTrusted;
    }
    if (!is_ground_station(from.sysid)) {
        return TrustVerdict::kStranger;
    }
    return concern == Concern::kVehicleState ? TrustVerdict::kNotVehicle : TrustVerdict::kTrusted;
}

}  // namespace gport::mavlink::bridge
