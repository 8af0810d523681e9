// One command, one photo (docs/mavlink.md, "One command, one photo"). With
// ArduPilot's CAMx_TYPE 6, a ground station's IMAGE_START_CAPTURE or
// DO_DIGICAM_CONTROL sent to the vehicle reaches the camera twice: ArduPilot
// forwards the ground station's command and, about 0.3 ms later, sends its
// own IMAGE_START_CAPTURE to 1/100. Both mean the same photo.
//
// The rule: a single-photo command (IMAGE_START_CAPTURE for one image, or a
// DO_DIGICAM_CONTROL shot) that arrives within kWindow of the photo begun
// last, from another sender, one of the two being the vehicle's system, is
// that photo again: it is not taken twice, and it is answered with that
// photo's result (when it completes, or at once when it already has).
// Pure: the caller gives the time.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace gport::mavlink::bridge {

class PhotoMerge {
  public:
    using Clock = std::chrono::steady_clock;
    // A forwarded command and the autopilot's own are 0.3 ms apart (one
    // pass of ArduPilot's loop); a person's or a trigger's two photos are
    // hundreds of ms apart, and interval captures at least
    // kMinImageIntervalS (0.5 s).
    static constexpr std::chrono::milliseconds kWindow{50};

    struct Sender {
        std::uint8_t sysid = 0;
        std::uint8_t compid = 0;
        bool operator==(const Sender&) const = default;
    };

    enum class Match {
        kNew,       // a photo of its own
        kInFlight,  // the photo begun last, still with gportd: answer when it completes
        kDone,      // the photo begun last, already answered: answer with result()
    };

    // A single-photo command from `sender` arrived at `now`; `vehicle` is
    // the vehicle's system id.
    Match match(Sender sender, std::uint8_t vehicle, Clock::time_point now) const;
    // The photo of a kNew command was begun (sent to gportd).
    void begun(Sender sender, Clock::time_point now);
    // That photo completed with this MAV_RESULT.
    void done(std::uint8_t result);
    std::optional<std::uint8_t> result() const { return result_; }
    // How long after the photo's command `now` is.
    Clock::duration since_begun(Clock::time_point now) const;

  private:
    std::optional<Sender> sender_;
    Clock::time_point at_{};
    std::optional<std::uint8_t> result_;
};

}  // namespace gport::mavlink::bridge
