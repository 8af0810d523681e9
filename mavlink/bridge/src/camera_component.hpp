// gport-mavlink's camera component, compid 100 (docs/mavlink.md, "The camera
// component"): its heartbeat and the requests for its messages; photos
// (single, by interval, DIGICAM shots) and video as gportd `photo` /
// `record` with the vehicle's position as the capture's `meta`; and
// CAMERA_IMAGE_CAPTURED after each photo, kept for a ground station that
// missed one and asks again (image_history.hpp).
//
// It is the one photo path and the one record path: the gimbal component's
// (154) IMAGE_START_CAPTURE, IMAGE_STOP_CAPTURE and VIDEO_START/STOP_CAPTURE
// come here too (command() with the gimbal's compid), answered from 154.
// What it needs of the bridge (the transport, gportd, the vehicle's state)
// it asks through CameraHost, which the Bridge implements.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "gport/base/token_bucket.hpp"
#include "gport/client/async_client.hpp"
#include "gport/mavlink/bridge/camera.hpp"
#include "gport/mavlink/bridge/image_count.hpp"
#include "gport/mavlink/bridge/image_history.hpp"
#include "gport/mavlink/bridge/mapping.hpp"
#include "gport/mavlink/bridge/options.hpp"
#include "gport/mavlink/bridge/photo_merge.hpp"
#include "gport/mavlink/messages.hpp"
#include "logbook.hpp"
#include "transport.hpp"

namespace gport::mavlink::bridge {

// Who sent a command: its header (for the ACK's target) and its origin
// (where the reply goes: the request's sender, not whoever is the peer by
// the time gportd answers).
struct Requester {
    Header header;
    Origin origin;
};

class CameraHost {
  public:
    // Sends from component `compid` (0: the gimbal's) to `to` (empty: the peer).
    virtual void send_from(std::uint8_t compid, const Message& message, const Origin& to) = 0;
    virtual void ack_from(std::uint8_t compid, const Requester& to, std::uint16_t command,
                          std::uint8_t result) = 0;
    virtual client::AsyncClient& gportd() = 0;
    virtual bool gportd_connected() const = 0;
    virtual Health health() const = 0;
    virtual std::uint32_t time_boot_ms() const = 0;
    virtual std::uint8_t vehicle_sysid() const = 0;
    // The vehicle's yaw when fresh (logs a change of its source).
    virtual std::optional<double> vehicle_yaw_deg() = 0;
    virtual const std::optional<client::AttitudeSample>& newest_sample() const = 0;
    // How often the position stream was asked of the autopilot.
    virtual std::uint32_t position_requests() const = 0;

  protected:
    virtual ~CameraHost() = default;
};

class CameraComponent {
  public:
    using Clock = std::chrono::steady_clock;

    CameraComponent(boost::asio::io_context& io, const Options& options, Logbook& log,
                    CameraHost& host);

    // Whether the component is announced (not --no-camera).
    bool enabled() const { return options_.camera; }
    // Addressed to the camera: its component id, or broadcast and a camera
    // command (a broadcast photo is taken once, by the camera, not by both).
    bool addressed(const CommandLong& command) const;
    // A command to the camera (compid 100).
    void on_command(const Requester& from, const CommandLong& command);
    // The gimbal component's image and video commands, answered from
    // `compid`. An IMAGE_START_CAPTURE there is one photo whatever its
    // parameters, as it always was at 154 (gimbal managers send it bare).
    void on_gimbal_command(const Requester& from, const CommandLong& command, std::uint8_t compid);
    // The vehicle's newest position (already checked: position.hpp).
    void on_position(const GlobalPositionInt& position, Clock::time_point when);
    void send_heartbeat(const Origin& to = std::nullopt);
    // At start: the image count kept in the state directory.
    void load_image_count();

  private:
    void request(const Requester& from, const CommandLong& command);
    void resend_images(const Requester& from, const CommandLong& command);
    void start_images(const Requester& from, const CommandLong& command);
    void begin_interval(const Requester& from, const CommandLong& command, const ImagePlan& plan);
    bool busy(const Requester& from, const CommandLong& command, std::uint8_t compid);
    void image_tick();
    void stop_images();
    CameraCaptureStatus capture_status() const;
    void send(const Message& message, const Origin& to = std::nullopt);
    void ack(const Requester& to, std::uint16_t command, std::uint8_t result,
             std::uint8_t compid = kCameraCompid);

    // Photos (camera_photo.cpp).
    bool merged_photo(const Requester& from, const CommandLong& command, std::uint8_t compid);
    void begin_photo(const Requester& from, std::uint16_t command, std::uint8_t compid);
    void take_photo(const std::optional<Requester>& from, std::uint16_t command,
                    std::uint8_t compid);
    void photo_done(const std::optional<Requester>& from, std::uint16_t command,
                    std::uint8_t compid, const std::optional<client::Error>& error,
                    const client::PhotoReport& report, const client::CaptureStamp& stamp);
    ImageCapture image_captured(const std::optional<client::Error>& error,
                                const client::PhotoReport& report,
                                const client::CaptureStamp& stamp);
    void record(const Requester& from, std::uint16_t command, std::uint8_t compid, bool on,
                bool force);
    client::CaptureOptions capture_options() const;
    std::optional<GlobalPositionInt> fresh_position() const;
    void warn_no_position(std::int32_t image_index);

    const Options& options_;
    Logbook& log_;
    CameraHost& host_;
    boost::asio::steady_timer image_timer_;
    std::optional<std::pair<GlobalPositionInt, Clock::time_point>> position_;
    std::optional<ImagePlan> images_;
    std::uint32_t images_taken_ = 0;  // of the running interval capture
    ImageCount image_count_;          // photos taken, kept in the state directory
    ImageHistory image_history_;      // their CAMERA_IMAGE_CAPTURED, for a re-request
    base::TokenBucket resend_budget_{kImageResendPerSecond, kImageResendPerSecond};
    std::optional<Clock::time_point> recording_since_;
    bool photo_in_flight_ = false;
    // One camera call (photo, record) to gportd at a time; a camera command
    // arriving meanwhile is answered TEMPORARILY_REJECTED: a flood of them
    // cannot use up gportd's request budget (the autopilot's angles) or
    // grow the pending calls.
    bool call_in_flight_ = false;
    PhotoMerge photo_merge_;  // the photo begun last, for a second command of it
    // Answered when the photo completes: who sent it again, its command and
    // the component that answers.
    struct Merged {
        Requester from;
        std::uint16_t command = 0;
        std::uint8_t compid = 0;
    };
    std::vector<Merged> merged_;
    bool position_warned_ = false;  // a photo without a position: said once
};

}  // namespace gport::mavlink::bridge
