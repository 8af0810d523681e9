// gport-mavlink's signing session (signing_session.hpp) under the attacks
// of issue 30: a key holder's frame stamped 23 h ahead, and a timestamp
// file planted at 2^48 - 1. Our clock must stay within 30 s of the wall
// clock, a vehicle whose clock is right must never be refused, and
// replays and stale streams must still be.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "gport/mavlink/messages.hpp"
#include "signing_samples.hpp"
#include "signing_session.hpp"

namespace gport::mavlink::bridge {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kSecond = kTimestampsPerSecond;
constexpr std::uint64_t k23Hours = 23ULL * 3600 * kSecond;

std::uint64_t wall() {
    return signing_timestamp(std::chrono::system_clock::now());
}

SecretKey key() {
    return *parse_key_hex(testing::kNodeKeyHex);
}

// A HEARTBEAT from sysid/compid on `link`, signed with the key at `timestamp`.
Frame signed_heartbeat(std::uint8_t sysid, std::uint8_t link, std::uint64_t timestamp) {
    Heartbeat hb;
    hb.type = 2;
    hb.autopilot = 3;
    Frame frame = encode(hb, Header{0, sysid, 1}, true);
    sign(frame, key(), link, timestamp);
    return frame;
}

class SigningSessionTest : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("gport-mavlink-session-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        fs::permissions(dir_, fs::perms::owner_all);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::unique_ptr<SigningSession> open() {
        auto session = SigningSession::open(key(), dir_.string(), log_);
        EXPECT_TRUE(session) << (session ? "" : session.error().message);
        return session ? std::move(*session) : nullptr;
    }
    // The timestamp of the next frame the session sends.
    static std::uint64_t outgoing(SigningSession& session) {
        Frame frame = encode(Heartbeat{}, Header{0, 1, 154}, true);
        session.sign(frame);
        return signature_block_of(frame.bytes())->timestamp;
    }
    std::uint64_t stored() const {
        std::uint64_t value = 0;
        std::ifstream(dir_ / TimestampFile::kFileName) >> value;
        return value;
    }

    fs::path dir_;
    Logbook log_;
};

// The brief's attack: system 99 (not obeyed) holds the key and sends one
// frame 23 h ahead. The Verifier takes its signature; the Bridge refuses
// it by the trust rules and never calls follow(): nothing moves.
TEST_F(SigningSessionTest, AStrangersFrame23HoursAheadMovesNothing) {
    auto session = open();
    ASSERT_TRUE(session);
    const Frame attack = signed_heartbeat(99, 0, wall() + k23Hours);
    EXPECT_TRUE(session->admit(attack.view()));
    EXPECT_LT(outgoing(*session), wall() + kSecond);
    // The vehicle on a new link, its clock right: taken.
    EXPECT_TRUE(session->admit(signed_heartbeat(1, 5, wall()).view()));
    session->close();
    EXPECT_LT(stored(), wall() + kSecond);
}

// Even a frame we obey (the vehicle's, or a ground station whose clock is
// hours ahead) pulls ours at most 30 s ahead, and the vehicle's own new
// streams stay acceptable; replays and stale streams are still refused.
TEST_F(SigningSessionTest, AnObeyedFrame23HoursAheadPullsOursAtMost30Seconds) {
    auto session = open();
    ASSERT_TRUE(session);
    const Frame ahead = signed_heartbeat(255, 0, wall() + k23Hours);
    ASSERT_TRUE(session->admit(ahead.view()));
    session->follow(ahead.view());
    const std::uint64_t ours = outgoing(*session);
    EXPECT_GE(ours, wall() + SendClock::kMaxLead - kSecond);
    EXPECT_LE(ours, wall() + SendClock::kMaxLead + 1);
    const Frame vehicle = signed_heartbeat(1, 6, wall() - 10 * kSecond);
    EXPECT_TRUE(session->admit(vehicle.view())) << "a vehicle 10 s behind the clock";
    EXPECT_FALSE(session->admit(vehicle.view())) << "its replay";
    EXPECT_FALSE(session->admit(signed_heartbeat(1, 7, wall() - 2 * kOneMinute).view()))
        << "a new stream two minutes old";
    EXPECT_FALSE(session->admit(ahead.view())) << "the attack's replay";
    using enum SignatureCheck;
    EXPECT_EQ(session->counts()[static_cast<std::size_t>(kReplayed)], 2U);
    EXPECT_EQ(session->counts()[static_cast<std::size_t>(kTooOld)], 1U);
    session->close();
    EXPECT_LE(stored(), wall() + SendClock::kMaxLead + 1);
}

// Item 2: a file planted (or left by an older version) at 2^48 - 1 is not
// taken: the next start signs near the clock and takes the vehicle.
TEST_F(SigningSessionTest, APlantedSaturatedTimestampIsNotTaken) {
    std::ofstream(dir_ / TimestampFile::kFileName) << kMaxTimestamp << "\n";
    auto session = open();
    ASSERT_TRUE(session);
    EXPECT_LE(stored(), wall() + SendClock::kMaxLead) << "written back bounded at start";
    const std::uint64_t ours = outgoing(*session);
    EXPECT_LE(ours, wall() + SendClock::kMaxLead + 1);
    EXPECT_GE(ours, wall() - kSecond);
    EXPECT_TRUE(session->admit(signed_heartbeat(1, 3, wall()).view()));
}

// A stored value a little ahead (a crash's reservation, or our clock a
// few seconds back) is still where we start: peers that saw our frames
// must see newer ones.
TEST_F(SigningSessionTest, AStoredValue20SecondsAheadIsKept) {
    const std::uint64_t ahead = wall() + 20 * kSecond;
    std::ofstream(dir_ / TimestampFile::kFileName) << ahead << "\n";
    auto session = open();
    ASSERT_TRUE(session);
    EXPECT_GT(outgoing(*session), ahead);
    EXPECT_TRUE(session->admit(signed_heartbeat(1, 3, wall() - 20 * kSecond).view()));
}

}  // namespace
}  // namespace gport::mavlink::bridge
