// Camera commands at a rate a camera can follow (issue 30): a flood of
// photos from any number of clients gets -32005 naming the limit once the
// burst is spent, nothing more reaches the line, and status counts them.
#include "gport/daemon/core/camera_gate.hpp"

#include <gmock/gmock.h>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using ::testing::HasSubstr;

// The frames a gate sent (none when the device refuses them).
struct SentFrames {
    std::vector<protocol::Frame> frames;
    bool link_up = true;
    daemon::CameraGate::Send send() {
        return [this](const protocol::Frame& f) -> std::optional<daemon::CommandError> {
            if (!link_up) {
                return daemon::CommandError{daemon::ErrorCode::kLinkDown, "link down"};
            }
            frames.push_back(f);
            return std::nullopt;
        };
    }
};

TEST(CameraGate, ABurstOfOneSecondThenTheRate) {
    config::CameraConfig config;
    config.max_commands_per_s = 4;
    SentFrames line;
    daemon::CameraGate gate(config, quiet_logger(), line.send());
    const auto t0 = std::chrono::steady_clock::time_point{} + 100s;
    for (int i = 0; i < 4; ++i) {
        EXPECT_FALSE(gate.admit(t0).has_value()) << i;
    }
    const auto refused = gate.admit(t0);
    ASSERT_TRUE(refused.has_value());
    EXPECT_EQ(refused->code, daemon::ErrorCode::kTooManyRequests);
    EXPECT_THAT(refused->message, HasSubstr("camera.max_commands_per_s"));
    EXPECT_THAT(refused->message, HasSubstr("4 per second"));
    EXPECT_THAT(refused->message, HasSubstr("try again in 250 ms"));
    EXPECT_FALSE(gate.admit(t0 + 250ms).has_value());
    EXPECT_EQ(gate.status().refused, 1u);
}

TEST(CameraGate, ASlowRateStillAllowsOneCommand) {
    config::CameraConfig config;
    config.max_commands_per_s = 0.1;
    SentFrames line;
    daemon::CameraGate gate(config, quiet_logger(), line.send());
    const auto t0 = std::chrono::steady_clock::time_point{} + 100s;
    EXPECT_FALSE(gate.admit(t0).has_value());
    EXPECT_TRUE(gate.admit(t0 + 5s).has_value());
    EXPECT_FALSE(gate.admit(t0 + 10s).has_value());
}

TEST_F(CoreFixture, APhotoFloodIsRefusedPastTheCameraLimitAndNothingMoreIsSent) {
    start({}, [](config::Config& c) { c.camera.max_commands_per_s = 5; });
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    int accepted = 0;
    int refused = 0;
    for (int i = 0; i < 200; ++i) {
        auto r = i % 2 == 0 ? core->photo(alice) : core->photo(bob);
        if (r.ok()) {
            ++accepted;
        } else {
            EXPECT_EQ(r.error().code, daemon::ErrorCode::kTooManyRequests);
            ++refused;
        }
    }
    EXPECT_GE(accepted, 5);
    EXPECT_LE(accepted, 7) << "a burst of one second's worth, over all clients";
    EXPECT_EQ(core->status().camera.refused, static_cast<std::uint64_t>(refused));
    ASSERT_TRUE(
        run_until([&] { return frames_with("0x86") == static_cast<std::size_t>(accepted); }));
    run_for(100ms);
    EXPECT_EQ(frames_with("0x86"), static_cast<std::size_t>(accepted));
}

// The recording state is assumed (the protocol has one toggle and no way to
// read it): unknown until a toggle, forgotten when the device reopens.
TEST(CameraGate, TheRecordingStateIsWhatTheLastToggleMadeIt) {
    SentFrames line;
    daemon::CameraGate gate(config::CameraConfig{}, quiet_logger(), line.send());
    using daemon::RecordingState;
    const auto toggle_frame =
        protocol::encode(protocol::Camera{protocol::CameraAction::kToggleRecording});
    EXPECT_EQ(gate.recording(), RecordingState::kUnknown);

    const daemon::RecordRequest on{true, false};
    const auto refused = gate.check_record(on);
    ASSERT_TRUE(refused.has_value());
    EXPECT_EQ(refused->code, daemon::ErrorCode::kInvalidParams);
    EXPECT_THAT(refused->message, HasSubstr("\"force\": true"));

    const daemon::RecordRequest forced_on{true, true};
    EXPECT_FALSE(gate.check_record(forced_on).has_value());
    auto result = gate.record(forced_on, 42);
    ASSERT_TRUE(result.ok());
    EXPECT_TRUE(result->sent);
    EXPECT_EQ(result->recording, RecordingState::kOn);
    ASSERT_EQ(line.frames.size(), 1u);
    EXPECT_EQ(line.frames[0], toggle_frame);

    EXPECT_FALSE(gate.check_record(on).has_value());
    result = gate.record(on, 42);  // already on: nothing to send
    ASSERT_TRUE(result.ok());
    EXPECT_FALSE(result->sent);
    EXPECT_EQ(line.frames.size(), 1u);
    EXPECT_TRUE(gate.toggle_needed(forced_on));

    const daemon::RecordRequest toggle{std::nullopt, false};
    EXPECT_EQ(gate.record(toggle, 42)->recording, RecordingState::kOff);
    EXPECT_EQ(line.frames.size(), 2u);

    line.link_up = false;  // not sent: the state stays
    const auto down = gate.record(toggle, 42);
    ASSERT_FALSE(down.ok());
    EXPECT_EQ(down.error().code, daemon::ErrorCode::kLinkDown);
    EXPECT_EQ(gate.recording(), RecordingState::kOff);

    gate.device_opened();
    EXPECT_EQ(gate.recording(), RecordingState::kUnknown);
    EXPECT_EQ(gate.toggled(toggle), RecordingState::kUnknown);  // a toggle of unknown
}

}  // namespace
}  // namespace gport::testing
