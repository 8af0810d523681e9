// The simulator end to end over a real pseudo-terminal, seen from the client
// side as gportd sees it. Bounds are generous: the machine is small and busy.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>

#include "gport/sim/recording.hpp"
#include "pty_helpers.hpp"

namespace gport::sim {
namespace {

namespace p = gport::protocol;
using namespace gport::sim::testing;

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / (name + "." + std::to_string(::getpid())))
        .string();
}

TEST(PtySimulator, StreamsAttitudeAtTheSetRate) {
    SimOptions o;
    o.model.stream_rate_hz = 50;
    SimThread sim(o);
    EXPECT_EQ(sim.path().rfind("/dev/pts/", 0), 0U);
    Client client(sim.path());
    ASSERT_TRUE(client.ok());
    const auto d = decode_all(client.read_for(2000ms));
    EXPECT_GE(d.attitudes().size(), 50U);  // 100 expected
    EXPECT_LE(d.attitudes().size(), 150U);
    EXPECT_EQ(d.stats.garbage_bytes, 0U);
    EXPECT_TRUE(sim.traced("\"event\":\"peer_open\""));
}

TEST(PtySimulator, CommandsChangeWhatAttitudeReports) {
    SimOptions o;
    o.model.form = AttitudeForm::kLong24;
    SimThread sim(o);
    Client client(sim.path());
    ASSERT_TRUE(eventually([&] { return sim.stats().peer_opens == 1; }));
    client.send(p::Control::speed_of({0, 0, 3000}));
    auto d = decode_all(client.read_for(600ms));
    ASSERT_FALSE(d.attitudes().empty());
    const auto moving = d.attitudes().back();
    EXPECT_GT(moving.hall.yaw, 600);  // 30 °/s for most of 0.6 s
    EXPECT_EQ(moving.rates->hall.yaw, 3000);

    client.send(p::Control::angle_of({0, -2000, 0}));
    client.send(p::GetSettings{});
    d = decode_all(client.read_for(1500ms));
    EXPECT_EQ(d.attitudes().back().hall.pitch, -2000);
    const auto has_settings = std::any_of(d.messages.begin(), d.messages.end(), [](auto& m) {
        return std::holds_alternative<p::SettingsReport>(m);
    });
    EXPECT_TRUE(has_settings);
    EXPECT_TRUE(sim.traced("\"cmd\":\"0x85\",\"mode\":\"speed\",\"speed\":[0,0,3000]"));
}

TEST(PtySimulator, OutputIsDroppedWhileNobodyListens) {
    SimOptions o;
    o.model.stream_rate_hz = 1000;
    SimThread sim(o);
    std::this_thread::sleep_for(500ms);
    EXPECT_GT(sim.stats().bytes_dropped, 0U);
    EXPECT_EQ(sim.stats().bytes_written, 0U);
    Client client(sim.path());
    // No backlog: what arrives is about the stream since the open, not 0.5 s of it.
    const auto first = client.read_for(50ms);
    EXPECT_LT(first.size(), 400 * p::frame_size(12));
}

TEST(PtySimulator, AClientThatDoesNotReadNeverBlocksTheSimulator) {
    SimOptions o;
    o.model.stream_rate_hz = 5000;
    SimThread sim(o);
    Client client(sim.path());
    std::this_thread::sleep_for(1500ms);  // the pty buffer fills up
    const auto stats = sim.stats();       // answered: the io thread is not stuck
    EXPECT_GT(stats.bytes_dropped, 0U);
    EXPECT_GT(stats.model.attitude_frames, 2000U);
    EXPECT_FALSE(decode_all(client.read_for(200ms)).attitudes().empty());
}

TEST(PtySimulator, PausedReadingFillsTheLineAndResumingDrainsItInOrder) {
    SimThread sim({});
    Client client(sim.path());
    ASSERT_TRUE(eventually([&] { return sim.stats().peer_opens == 1; }));
    sim.on_io([](PtySimulator& s) {
        s.pause_reading();
        return 0;
    });
    EXPECT_TRUE(sim.traced("\"event\":\"reading_paused\""));
    const auto photo = p::encode(p::Camera{p::CameraAction::kPhoto});
    std::size_t written = 0;
    // Until the kernel's buffer is full (EAGAIN); a partly written frame
    // would never complete, so only whole writes count.
    while (written < 100000 &&
           client.try_write(photo.bytes()) == static_cast<ssize_t>(photo.size())) {
        ++written;
    }
    ASSERT_LT(written, 100000U) << "writes never blocked: the simulator kept reading";
    client.read_for(200ms);  // attitude keeps coming while the line is stalled
    EXPECT_FALSE(sim.traced("\"action\":\"photo\""));
    sim.on_io([](PtySimulator& s) {
        s.resume_reading();
        return 0;
    });
    ASSERT_TRUE(eventually([&] {
        const auto t = sim.trace();
        return std::count_if(t.begin(), t.end(), [](const std::string& l) {
                   return l.find("\"action\":\"photo\"") != std::string::npos;
               }) >= static_cast<long>(written);
    }));
    EXPECT_TRUE(sim.traced("\"event\":\"reading_resumed\""));
    EXPECT_EQ(sim.stats().model.crc_errors, 0U);
}

// --baud: bytes the client wrote at once are read no faster than the line
// carries them, and each frame is traced at its last byte's arrival. Only
// the lower bound (the line's own time) is checked: it holds however slow
// the machine is.
TEST(PtySimulator, AtTheLineRateFramesWaitAndAreTimedByTheirLastByte) {
    SimOptions o;
    o.baud = 115200;
    o.model.stream_rate_hz = 0;
    SimThread sim(o);
    Client client(sim.path());
    ASSERT_TRUE(eventually([&] { return sim.stats().peer_opens == 1; }));
    const auto photo = p::encode(p::Camera{p::CameraAction::kPhoto});
    constexpr int kFrames = 100;
    for (int i = 0; i < kFrames; ++i) {
        client.write(photo.bytes());
    }
    const auto photos = [&] {
        std::vector<double> t;
        for (const auto& line : sim.trace()) {
            if (line.find("\"action\":\"photo\"") != std::string::npos) {
                t.push_back(std::stod(line.substr(line.find(':') + 1)));
            }
        }
        return t;
    };
    ASSERT_TRUE(eventually([&] { return photos().size() == kFrames; }));
    const auto t = photos();
    const double line_ms = (kFrames - 1) * photo.size() * 10 * 1000.0 / 115200;
    EXPECT_GE(t.back() - t.front(), line_ms - 0.2);  // the trace rounds to 0.1 ms
    EXPECT_GE(sim.stats().read_backlog_max, photo.size());
}

TEST(PtySimulator, BaudOutsideItsRangeIsRefused) {
    SimOptions o;
    o.baud = kMinBaud - 1;
    EXPECT_TRUE(validate(o).has_value());
    o.baud = kMaxBaud;
    EXPECT_FALSE(validate(o).has_value());
}

TEST(PtyFaults, NoiseShowsAsGarbageAndFramesStillDecode) {
    SimOptions o;
    o.faults.noise_bytes_per_s = 500;
    SimThread sim(o);
    Client client(sim.path());
    const auto d = decode_all(client.read_for(1500ms));
    EXPECT_GT(d.stats.garbage_bytes, 100U);
    EXPECT_GT(d.attitudes().size(), 20U);
}

TEST(PtyFaults, CorruptedCrcsAreCountedByTheClientsDecoder) {
    SimOptions o;
    o.faults.corrupt_fraction = 0.5;
    SimThread sim(o);
    Client client(sim.path());
    const auto d = decode_all(client.read_for(1500ms));
    EXPECT_GT(d.stats.crc_errors, 5U);
    EXPECT_GT(d.attitudes().size(), 5U);
}

TEST(PtyFaults, SplitWritesArriveInPiecesAndStillDecode) {
    SimOptions o;
    o.faults.shape = WriteShape::kSplit;
    o.pace = true;  // 86.8 µs between bytes, so the pieces are visible
    SimThread sim(o);
    Client client(sim.path());
    const auto bytes = client.read_for(1500ms);
    const auto& sizes = client.read_sizes();
    ASSERT_FALSE(sizes.empty());
    EXPECT_LT(*std::min_element(sizes.begin(), sizes.end()), p::frame_size(12));
    EXPECT_GT(decode_all(bytes).attitudes().size(), 20U);
}

TEST(PtyFaults, MergedWritesCarrySeveralFrames) {
    SimOptions o;
    o.faults.shape = WriteShape::kMerge;
    o.faults.merge_count = 5;
    SimThread sim(o);
    Client client(sim.path());
    const auto bytes = client.read_for(1500ms);
    const auto& sizes = client.read_sizes();
    ASSERT_FALSE(sizes.empty());
    EXPECT_GE(*std::max_element(sizes.begin(), sizes.end()), 5 * p::frame_size(12));
    EXPECT_GT(decode_all(bytes).attitudes().size(), 20U);
}

TEST(PtyFaults, SilenceLeavesAGap) {
    SimOptions o;
    o.faults.silence_every = 300ms;
    o.faults.silence_for = 600ms;
    SimThread sim(o);
    Client client(sim.path());
    client.read_for(2500ms);
    const auto& times = client.read_times();
    ASSERT_GE(times.size(), 2U);
    std::chrono::steady_clock::duration gap{};
    for (std::size_t i = 1; i < times.size(); ++i) {
        gap = std::max(gap, times[i] - times[i - 1]);
    }
    EXPECT_GE(gap, 450ms);
    EXPECT_TRUE(sim.traced("\"event\":\"silence_start\""));
    EXPECT_TRUE(sim.traced("\"event\":\"silence_end\""));
}

TEST(PtyFaults, VanishClosesThePtyAndTheLinkComesBack) {
    const auto link = temp_path("gport-sim-vanish");
    SimOptions o;
    o.link_path = link;
    o.faults.vanish_every = 700ms;
    o.faults.vanish_for = 500ms;
    SimThread sim(o);
    EXPECT_EQ(sim.path(), link);
    Client first(link);
    ASSERT_TRUE(first.ok());
    EXPECT_FALSE(decode_all(first.read_for(300ms)).attitudes().empty());
    first.read_for(3000ms);
    EXPECT_TRUE(first.failed());  // EIO or EOF: the device went away under the reader
    EXPECT_TRUE(eventually([&] { return sim.traced("\"event\":\"vanish\""); }));

    ASSERT_TRUE(eventually([&] { return sim.traced("\"event\":\"reappear\""); }));
    std::unique_ptr<Client> again;
    ASSERT_TRUE(eventually([&] {
        again = std::make_unique<Client>(link);
        return again->ok();
    }));
    EXPECT_FALSE(decode_all(again->read_for(300ms)).attitudes().empty());
    again.reset();
    sim.stop();
    struct stat st {};
    EXPECT_NE(::lstat(link.c_str(), &st), 0) << "the link must be removed on stop";
}

std::vector<std::uint8_t> tx_bytes(const std::string& path) {
    std::vector<std::uint8_t> out;
    const auto loaded = load_recording(path);
    EXPECT_TRUE(loaded.ok());
    for (const auto& e : *loaded) {
        if (e.direction == Direction::kTx) {
            out.insert(out.end(), e.bytes.begin(), e.bytes.end());
        }
    }
    return out;
}

TEST(PtyRecording, ARecordingReplaysToTheSameBytes) {
    const auto file = temp_path("gport-sim-record");
    std::vector<std::uint8_t> live;
    {
        SimOptions o;
        o.record_path = file;
        SimThread sim(o);
        Client client(sim.path());
        ASSERT_TRUE(eventually([&] { return sim.stats().peer_opens == 1; }));
        client.send(p::Control::speed_of({0, 0, 5000}));
        client.send(p::GetSettings{});
        live = client.read_for(700ms);
        client.close();
        ASSERT_TRUE(eventually([&] { return sim.traced("peer_closed"); }));
    }
    const auto recorded = tx_bytes(file);
    ASSERT_GE(recorded.size(), live.size());
    EXPECT_TRUE(std::equal(live.begin(), live.end(), recorded.begin()));
    const auto rx = load_recording(file).value();
    EXPECT_TRUE(
        std::any_of(rx.begin(), rx.end(), [](auto& e) { return e.direction == Direction::kRx; }));

    SimOptions o;
    o.replay_path = file;
    SimThread replay(o);
    Client client(replay.path());
    std::vector<std::uint8_t> replayed;
    ASSERT_TRUE(eventually([&] {
        auto chunk = client.read_for(100ms);
        replayed.insert(replayed.end(), chunk.begin(), chunk.end());
        return replay.traced("replay_end");
    }));
    auto tail = client.read_for(200ms);
    replayed.insert(replayed.end(), tail.begin(), tail.end());
    EXPECT_EQ(replayed, recorded);
    std::filesystem::remove(file);
}

}  // namespace
}  // namespace gport::sim
