// Issue 12, item 5: a client that streams speed commands updates its own
// motion (no started/replaced events, rate-limited "updated" ones), and a
// lease stops a controller that hangs with its socket open.
#include <fmt/format.h>

#include <algorithm>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using daemon::EndReason;
using daemon::ErrorCode;
using daemon::Keepalive;
using daemon::MotionChange;

class Leases : public CoreFixture {
  protected:
    std::size_t count(MotionChange change) const {
        return static_cast<std::size_t>(std::ranges::count_if(
            recorder.motions, [&](const daemon::MotionEvent& e) { return e.change == change; }));
    }

    bool ended_with(EndReason reason) const {
        return !recorder.motions.empty() &&
               recorder.motions.back().change == MotionChange::kEnded &&
               recorder.motions.back().reason == reason;
    }
};

TEST_F(Leases, TheOwnersSpeedsUpdateItsMotionAndAreCoalesced) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    const auto began = std::chrono::steady_clock::now();
    constexpr int kCommands = 30;
    for (int i = 0; i < kCommands; ++i) {
        auto r = core->speed(alice, {0, 0, static_cast<std::int16_t>(500 + i)}, 5000ms);
        ASSERT_TRUE(r.ok()) << r.error().message;
        run_for(50ms);
    }
    const auto streamed = std::chrono::steady_clock::now() - began;
    ASSERT_TRUE(core->status().motion.has_value());
    EXPECT_EQ(core->status().motion->speed.yaw, 500 + kCommands - 1) << "the latest speed";
    EXPECT_EQ(core->status().counters.motion_updates, static_cast<std::uint64_t>(kCommands - 1));
    ASSERT_TRUE(core->stop(alice).ok());

    EXPECT_EQ(count(MotionChange::kStarted), 1U);
    EXPECT_EQ(count(MotionChange::kReplaced), 0U);
    EXPECT_EQ(count(MotionChange::kEnded), 1U);
    EXPECT_EQ(recorder.motions.front().change, MotionChange::kStarted);
    EXPECT_TRUE(ended_with(EndReason::kStop));
    // At most one per interval after the previous event (one more for rounding).
    const auto allowed = static_cast<std::size_t>(streamed / Keepalive::kUpdateNoteInterval) + 1;
    EXPECT_GE(count(MotionChange::kUpdated), 1U);
    EXPECT_LE(count(MotionChange::kUpdated), allowed);
    for (const auto& e : recorder.motions) {
        if (e.change == MotionChange::kUpdated) {
            EXPECT_GT(e.speed.yaw, 500) << "an update carries the newer speed";
        }
    }
    // Every command still went out at once.
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() >= 1; }));
    const auto speeds = speed_frames();
    EXPECT_TRUE(std::ranges::find(speeds, Json::array({0, 0, 500 + kCommands - 1})) !=
                speeds.end());
}

TEST_F(Leases, TheLeaseStopsAHungController) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 800}, 30000ms, false, 300ms).ok());
    // Updates renew the lease: the motion outlives several leases.
    for (int i = 0; i < 12; ++i) {
        run_for(100ms);
        ASSERT_TRUE(core->speed(alice, {0, 0, 800}, 30000ms, false, 300ms).ok());
    }
    EXPECT_TRUE(core->status().motion.has_value()) << "renewed by each update";
    EXPECT_EQ(count(MotionChange::kEnded), 0U);
    // The controller hangs: no more updates.
    ASSERT_TRUE(run_until([&] { return ended_with(EndReason::kLeaseExpired); }, 5s));
    EXPECT_FALSE(core->status().motion.has_value());
    ASSERT_TRUE(run_until([&] { return zero_speed_frames() >= 1; }, 5s));
    EXPECT_EQ(speed_frames().back(), Json::array({0, 0, 0}));
    EXPECT_EQ(count(MotionChange::kStarted), 1U);
    EXPECT_EQ(count(MotionChange::kEnded), 1U);
}

TEST_F(Leases, AnotherClientsSpeedStillReplaces) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 1000}, 5000ms).ok());
    ASSERT_TRUE(core->speed(alice, {0, 0, 1100}, 5000ms).ok());
    EXPECT_EQ(count(MotionChange::kReplaced), 0U);
    ASSERT_TRUE(core->speed(bob, {0, 0, -1000}, 5000ms).ok());
    EXPECT_EQ(recorder.motions.back().change, MotionChange::kReplaced);
    EXPECT_EQ(recorder.motions.back().owner->id, bob.id);
    ASSERT_TRUE(core->speed(bob, {0, 0, -1100}, 5000ms).ok());  // bob's own: an update
    EXPECT_EQ(count(MotionChange::kReplaced), 1U);
    EXPECT_EQ(count(MotionChange::kStarted), 1U);
    EXPECT_EQ(core->status().motion->owner->id, bob.id);
    EXPECT_EQ(core->status().counters.motion_updates, 2U);
}

TEST_F(Leases, ALeaseOutOfRangeIsRefusedNamingTheRange) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    const auto max = config::Config{}.keepalive.max_duration;
    for (const auto lease : {0ms, max + 1ms}) {
        auto r = core->speed(alice, {0, 0, 100}, 1000ms, false, lease);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().code, ErrorCode::kInvalidParams);
        EXPECT_NE(r.error().message.find("lease_ms"), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find(fmt::format("allowed 1 to {}", max.count())),
                  std::string::npos)
            << r.error().message;
    }
    EXPECT_TRUE(recorder.motions.empty());
}

}  // namespace
}  // namespace gport::testing
