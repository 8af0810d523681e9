// A simulated G-Port gimbal: a pure model driven by the clock it is given.
//
// The model owns no I/O and reads no clock. The caller moves its time with
// advance()/step() and feeds it downlink bytes with receive(); both return
// the frames the gimbal sends in answer (0x87 attitude when due, 0x14 and
// 0x16 replies). Tests step it deterministically; PtySimulator runs it live.
//
//   downlink  effect
//   0x13      answer 0x14 with the settings block
//   0x15      store the whole block (reserved bytes too), answer 0x16
//   0x85 1    speed: move at the given rates; stop speed_timeout after the last one
//   0x85 2    angle: slew to the target at slew_deg_s (clamped to the limits)
//   0x85 3    centre: slew to 0/0/0
//   0x85 4    lock: hold the current attitude
//   0x86 1/2  toggle recording / count a photo
//   other     counted (invalid, unexpected or bad), never answered
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gport/protocol/decoder.hpp"
#include "gport/protocol/frame.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::sim {

// Model time: the time since the model was created.
using Duration = std::chrono::nanoseconds;

// Roll, pitch, yaw in degrees (or degrees per second).
struct Vec3 {
    double roll = 0.0;
    double pitch = 0.0;
    double yaw = 0.0;
    friend bool operator==(const Vec3&, const Vec3&) = default;
};

enum class AttitudeForm { kShort12, kLong24 };  // 0x87 with 12 or 24 data bytes

// The settings a fresh simulated gimbal reports: reserved bytes spell
// "GPORTSIM" then 0x01 0x02 0x03, tail 0xA5, so tests can prove that a
// read-modify-write keeps them.
protocol::SettingsBlock default_settings();

struct ModelOptions {
    double stream_rate_hz = 50.0;  // 0x87 frames per second; 0 switches telemetry off
    AttitudeForm form = AttitudeForm::kShort12;
    double slew_deg_s = 90.0;  // angle and centre moves, per axis
    Duration speed_timeout = std::chrono::seconds(1);
    Vec3 limits{45.0, 90.0, 170.0};  // mechanical range: ± degrees per axis
    Vec3 base{};                     // aircraft attitude: imu = hall + base
    protocol::SettingsBlock settings = default_settings();
};

inline constexpr double kMaxStreamRateHz = 10000.0;

// Empty when the options are usable; otherwise what is wrong and what is allowed.
std::optional<std::string> validate(const ModelOptions& options);

struct ModelState {
    protocol::ControlMode mode = protocol::ControlMode::kLock;
    Vec3 hall;       // joint angles, degrees
    Vec3 hall_rate;  // degrees per second
    Vec3 imu;        // camera attitude, degrees (yaw wrapped to ±180)
    bool speed_active = false;
    bool recording = false;
    std::uint64_t photos = 0;
    protocol::SettingsBlock settings;
};

struct ModelStats {
    std::uint64_t bytes_received = 0;
    std::uint64_t frames_received = 0;    // valid frames, whatever their command
    std::uint64_t crc_errors = 0;         // candidates rejected for their CRC
    std::uint64_t header_errors = 0;      // candidates rejected for version or header sum
    std::uint64_t garbage_bytes = 0;      // bytes discarded by the decoder
    std::uint64_t invalid_frames = 0;     // valid CRC, content refused (length, mode, action)
    std::uint64_t unexpected_frames = 0;  // uplink or unknown commands sent to the gimbal
    std::uint64_t attitude_frames = 0;    // 0x87 sent
    std::uint64_t replies = 0;            // 0x14 and 0x16 sent
};

// One thing the model saw in received bytes, for tracing.
struct Received {
    enum class Kind { kFrame, kCrcError, kHeaderError, kInvalid, kUnexpected, kGarbage };
    Kind kind = Kind::kFrame;
    std::uint8_t command = 0;                  // kFrame, kInvalid, kUnexpected
    std::optional<protocol::Message> message;  // kFrame
    std::string detail;                        // kInvalid: the decoder's reason
    std::uint64_t bytes = 0;                   // kGarbage: bytes discarded
};

class GimbalModel {
  public:
    using Frames = std::vector<protocol::Frame>;
    using Listener = std::function<void(const Received&)>;

    // Throws std::invalid_argument when validate(options) refuses them.
    explicit GimbalModel(ModelOptions options = {});

    // Moves time forward; returns the 0x87 frames that fell due, in order.
    Frames advance(Duration dt);
    // Moves time to `now` (since model start); a time in the past is ignored.
    Frames step(Duration now);
    // Feeds downlink bytes at the current time; returns the replies.
    Frames receive(std::span<const std::uint8_t> bytes);

    // Called for every frame, bad frame and garbage run that receive() sees.
    void set_listener(Listener listener) { listener_ = std::move(listener); }

    Duration now() const { return now_; }
    // When the next 0x87 falls due; Duration::max() with telemetry off.
    Duration next_emission() const { return next_emit_; }
    ModelState state() const;
    const ModelStats& stats() const { return stats_; }
    const ModelOptions& options() const { return options_; }
    // The attitude a 0x87 sent now would carry.
    protocol::Attitude attitude() const;

  private:
    void integrate(Duration to);
    void handle(const protocol::FrameView& frame, Frames& out);
    void apply(const protocol::Control& control);
    void report_decoder_delta(const protocol::DecoderStats& before);
    void notify(Received r);
    Duration emission_time(std::uint64_t index) const;

    ModelOptions options_;
    protocol::Decoder decoder_;
    Listener listener_;
    ModelStats stats_;
    Duration now_{0};
    Duration next_emit_ = Duration::max();
    std::uint64_t emit_index_ = 1;

    protocol::ControlMode mode_ = protocol::ControlMode::kLock;
    std::array<double, 3> position_{};  // hall degrees
    std::array<double, 3> velocity_{};  // speed mode, degrees per second
    std::array<double, 3> target_{};    // angle and centre modes
    Duration speed_until_{0};
    bool recording_ = false;
    std::uint64_t photos_ = 0;
    protocol::SettingsBlock settings_;
};

// The frames' bytes back to back.
std::vector<std::uint8_t> to_bytes(std::span<const protocol::Frame> frames);

}  // namespace gport::sim
