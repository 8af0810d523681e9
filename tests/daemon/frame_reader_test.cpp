// FrameReader: the gimbal's bytes become typed messages for their handlers,
// stamped with the time they arrived; what does not decode is counted, never
// handed on.
#include "gport/daemon/core/frame_reader.hpp"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

#include <sstream>
#include <vector>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

namespace gp = gport::protocol;

struct Heard {
    std::vector<gp::Attitude> attitudes;
    std::vector<daemon::SteadyTime> arrived;
    std::vector<gp::SettingsBlock> reports;
    int acks = 0;
};

class FrameReaderTest : public ::testing::Test {
  protected:
    void feed(const std::vector<std::uint8_t>& bytes) { reader.feed(bytes); }

    boost::asio::io_context io;
    Heard heard;
    daemon::FrameReader reader{
        io, "/dev/test", quiet_logger(),
        daemon::FrameReader::Handlers{
            [this](const gp::Attitude& a, daemon::SteadyTime now, daemon::WallTime) {
                heard.attitudes.push_back(a);
                heard.arrived.push_back(now);
            },
            [this](const gp::SettingsBlock& block) { heard.reports.push_back(block); },
            [this] { ++heard.acks; }}};
};

std::vector<std::uint8_t> bytes_of(std::initializer_list<gp::Frame> frames) {
    std::vector<std::uint8_t> out;
    for (const auto& frame : frames) {
        out.insert(out.end(), frame.bytes().begin(), frame.bytes().end());
    }
    return out;
}

const gp::Attitude kAttitude{{100, -200, 300}, {1, 2, 3}, std::nullopt};

TEST_F(FrameReaderTest, EachMessageGoesToItsHandlerWithTheTimeItArrived) {
    gp::SettingsBlock block;
    block.dead_zone = 7;
    const auto before = std::chrono::steady_clock::now();
    feed(bytes_of({gp::encode(kAttitude), gp::encode(gp::SettingsReport{block}),
                   gp::encode(gp::SetSettingsAck{})}));
    ASSERT_EQ(heard.attitudes.size(), 1u);
    EXPECT_EQ(heard.attitudes[0], kAttitude);
    EXPECT_GE(heard.arrived[0], before);
    ASSERT_EQ(heard.reports.size(), 1u);
    EXPECT_EQ(heard.reports[0].dead_zone, 7);
    EXPECT_EQ(heard.acks, 1);
    EXPECT_EQ(reader.stats().frames, 3u);
    EXPECT_EQ(reader.bad_messages(), 0u);
}

TEST_F(FrameReaderTest, GarbageAndACorruptFrameAreCountedAndTheNextFrameStillArrives) {
    auto corrupt = bytes_of({gp::encode(kAttitude)});
    corrupt.back() ^= 0xFF;  // the CRC's last byte
    std::vector<std::uint8_t> stream{0x00, 0x55, 0x13};
    stream.insert(stream.end(), corrupt.begin(), corrupt.end());
    const auto good = bytes_of({gp::encode(kAttitude)});
    stream.insert(stream.end(), good.begin(), good.end());
    feed(stream);
    EXPECT_EQ(heard.attitudes.size(), 1u);
    EXPECT_EQ(reader.stats().crc_errors, 1u);
    EXPECT_GT(reader.stats().garbage_bytes, 0u);
}

TEST_F(FrameReaderTest, AFrameWhoseDataDoesNotDecodeIsABadMessageNotAnAttitude) {
    const std::vector<std::uint8_t> three{1, 2, 3};  // 0x87 carries 12 or 24 bytes
    feed(bytes_of({gp::Frame::make(0x87, three)}));
    EXPECT_TRUE(heard.attitudes.empty());
    EXPECT_EQ(reader.bad_messages(), 1u);
}

TEST_F(FrameReaderTest, ACommandItDoesNotHandleIsIgnored) {
    feed(bytes_of({gp::encode(gp::Camera{gp::CameraAction::kPhoto})}));
    EXPECT_TRUE(heard.attitudes.empty());
    EXPECT_TRUE(heard.reports.empty());
    EXPECT_EQ(heard.acks, 0);
    EXPECT_EQ(reader.bad_messages(), 0u);
}

TEST_F(FrameReaderTest, AResetDropsTheFrameTheDeviceClosedInTheMiddleOf) {
    const auto frame = bytes_of({gp::encode(kAttitude)});
    const auto half = static_cast<std::ptrdiff_t>(frame.size() / 2);
    const std::vector<std::uint8_t> first(frame.begin(), frame.begin() + half);
    const std::vector<std::uint8_t> second(frame.begin() + half, frame.end());
    feed(first);
    feed(second);
    EXPECT_EQ(heard.attitudes.size(), 1u);  // halves of one read make the frame
    feed(first);
    reader.reset();
    feed(second);
    EXPECT_EQ(heard.attitudes.size(), 1u);  // not across a reopen
}

// A noisy line is one journal line per interval that had errors, naming the
// device and the counts of that interval; a quiet interval logs nothing.
TEST(FrameReaderQuality, ANoisyIntervalIsOneSummaryAndAQuietOneIsNone) {
    using namespace std::chrono_literals;
    boost::asio::io_context io;
    std::ostringstream out;
    auto log = std::make_shared<spdlog::logger>(
        "test", std::make_shared<spdlog::sinks::ostream_sink_st>(out));
    log->set_pattern("%v");
    daemon::FrameReader reader(io, "/dev/test", log,
                               daemon::FrameReader::Handlers{
                                   [](const gp::Attitude&, daemon::SteadyTime, daemon::WallTime) {},
                                   [](const gp::SettingsBlock&) {}, [] {}},
                               50ms);
    reader.start();
    reader.feed(std::vector<std::uint8_t>(100, 0x00));
    for (int i = 0; i < 100 && out.str().empty(); ++i) {
        io.run_one_for(100ms);
    }
    EXPECT_EQ(out.str(),
              "noisy line on /dev/test: 0 CRC errors, 0 header errors, 100 garbage bytes in the "
              "last 0.05 s\n");
    out.str("");
    io.run_for(200ms);  // quiet intervals
    EXPECT_EQ(out.str(), "");
    reader.stop();
}

}  // namespace
}  // namespace gport::testing
