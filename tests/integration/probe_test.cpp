// Issue 32, item 4: `gportd --probe` finds the G-Port among decoys — gport-sim
// on its pty among a pty that chatters bytes that are no G-Port frames, a
// silent pty, a missing path and a plain file — and a missing device's log
// line names the serial devices there are.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "harness.hpp"

namespace gport::testing {
namespace {

// A pseudo-terminal whose slave is linked at `link`. A chattering one gets
// bytes that hold no valid G-Port frame (0xAE never starts one: every byte
// is below 0x80) every 20 ms; a flooding one as fast as they are read.
class Decoy {
  public:
    enum class Kind { kSilent, kChatter, kFlood };

    Decoy(const std::string& link, Kind kind) {
        EXPECT_EQ(::openpty(&master_, &slave_, nullptr, nullptr, nullptr), 0);
        std::filesystem::create_symlink(::ptsname(master_), link);
        if (kind == Kind::kSilent) {
            return;
        }
        ::fcntl(master_, F_SETFL, O_NONBLOCK);  // a full pty never blocks the writer
        const auto pause = kind == Kind::kChatter ? 20ms : 0ms;
        writer_ = std::thread([this, pause] {
            std::minstd_rand random(7);
            std::array<unsigned char, 4096> bytes{};
            while (!stop_) {
                for (auto& b : bytes) {
                    b = static_cast<unsigned char>(random() % 0x80);
                }
                const auto n = ::write(master_, bytes.data(), pause > 0ms ? 64 : bytes.size());
                std::this_thread::sleep_for(n < 0 ? 1ms : pause);
            }
        });
    }
    ~Decoy() {
        stop_ = true;
        if (writer_.joinable()) {
            writer_.join();
        }
        ::close(master_);
        ::close(slave_);
    }

  private:
    int master_ = -1;
    int slave_ = -1;
    std::atomic<bool> stop_{false};
    std::thread writer_;
};

struct Probe {
    int status = -1;
    std::vector<std::string> lines;
    std::string text() const {
        std::string all;
        for (const auto& l : lines) {
            all += l + "\n";
        }
        return all;
    }
    // The report's line for `device`.
    std::string line_of(const std::string& device) const {
        for (const auto& l : lines) {
            if (l.rfind(device, 0) == 0) {
                return l;
            }
        }
        return "";
    }
};

Probe probe(std::vector<std::string> devices) {
    devices.insert(devices.begin(), {GPORTD_PATH, "--probe"});
    Process process(devices);
    Probe p;
    while (auto line = process.next_line(30s)) {
        p.lines.push_back(*line);
    }
    p.status = process.wait(30s).value_or(-1);
    return p;
}

TEST(Probe, FindsTheGportAmongDecoysAndSaysWhatEachOneIs) {
    TempDir dir;
    SimProcess sim(dir);
    Decoy chatty(dir.file("chatty"), Decoy::Kind::kChatter);
    Decoy silent(dir.file("silent"), Decoy::Kind::kSilent);
    std::ofstream(dir.file("plain")) << "not a tty\n";
    const auto p = probe(
        {dir.file("chatty"), sim.link(), dir.file("silent"), dir.file("none"), dir.file("plain")});
    EXPECT_EQ(p.status, 0) << p.text();
    EXPECT_NE(p.lines.at(0).find("listening 1.5 s at 115200 baud on 5 devices"), std::string::npos)
        << p.text();
    EXPECT_NE(p.line_of(sim.link()).find("G-Port: "), std::string::npos) << p.text();
    EXPECT_NE(p.line_of(sim.link()).find("attitude frames (0x87)"), std::string::npos) << p.text();
    EXPECT_NE(p.line_of(dir.file("chatty"))
                  .find("0 G-Port frames: another device, or not at "
                        "115200 baud"),
              std::string::npos)
        << p.text();
    EXPECT_NE(p.line_of(dir.file("silent")).find("silent (nothing received)"), std::string::npos)
        << p.text();
    EXPECT_NE(p.line_of(dir.file("none")).find("no such device"), std::string::npos) << p.text();
    EXPECT_NE(p.line_of(dir.file("plain")).find("not a serial device"), std::string::npos)
        << p.text();
    EXPECT_NE(p.text().find("G-Port on " + sim.link() + ". Set it in gportd's config"),
              std::string::npos)
        << p.text();
    EXPECT_NE(p.text().find("\"serial\": {\"device\": \"" + sim.link() + "\"}"), std::string::npos)
        << p.text();
}

TEST(Probe, NoGportAmongDecoysExits1AndSaysWhatToCheck) {
    TempDir dir;
    Decoy chatty(dir.file("chatty"), Decoy::Kind::kChatter);
    const auto p = probe({dir.file("chatty"), dir.file("none")});
    EXPECT_EQ(p.status, 1) << p.text();
    EXPECT_NE(p.text().find("No G-Port found. Is it powered and wired"), std::string::npos)
        << p.text();
}

// The attacker: a device that never stops sending (a pty written as fast
// as it is read) cannot hold the probe past its listening time, and what it
// sends is counted, not kept.
TEST(Probe, ADeviceThatFloodsCannotHoldTheProbe) {
    TempDir dir;
    SimProcess sim(dir);
    Decoy flood(dir.file("flood"), Decoy::Kind::kFlood);
    const auto start = std::chrono::steady_clock::now();
    const auto p = probe({dir.file("flood"), sim.link()});
    const auto took = std::chrono::steady_clock::now() - start;
    EXPECT_EQ(p.status, 0) << p.text();
    EXPECT_NE(p.line_of(dir.file("flood")).find("bytes, 0 G-Port frames"), std::string::npos)
        << p.text();
    EXPECT_NE(p.line_of(sim.link()).find("G-Port: "), std::string::npos) << p.text();
    EXPECT_LT(took, 20s) << "listening is 1.5 s; generous for a loaded machine";
}

TEST(Probe, TwoNamesOfOneDeviceAreListenedOnOnce) {
    TempDir dir;
    SimProcess sim(dir);
    const auto target = std::filesystem::canonical(sim.link()).string();
    const auto p = probe({sim.link(), target});
    EXPECT_EQ(p.status, 0) << p.text();
    EXPECT_NE(p.lines.at(1).find(sim.link() + " (" + target + ")"), std::string::npos) << p.text();
    EXPECT_EQ(p.line_of(target), "") << "listed once, under the first name:\n" << p.text();
}

TEST(Probe, AMissingDeviceIsLoggedWithTheSerialDevicesThereAre) {
    TempDir dir;
    // gportd's log is on stderr: a shell joins it to the stdout the test reads.
    DaemonProcess daemon(dir, {"--device", dir.file("gimbal")}, {}, "",
                         {"/bin/sh", "-c", "exec \"$0\" \"$@\" 2>&1"});
    const auto line = daemon.process().wait_line(
        [](const std::string& l) { return l.find("cannot open device") != std::string::npos; },
        20s);
    ASSERT_TRUE(line.has_value());
    EXPECT_TRUE(line->find("; serial devices here: ") != std::string::npos ||
                line->find("; no serial devices here (is the adapter plugged in?") !=
                    std::string::npos)
        << *line;
    EXPECT_TRUE(line->find("`gportd --probe` to find it") != std::string::npos ||
                line->find("no serial devices here") != std::string::npos)
        << *line;
}

}  // namespace
}  // namespace gport::testing
