// Issue 32, item 4: `gportd --probe` finds the G-Port among decoys — gport-sim
// on its pty among a pty that chatters bytes that are no G-Port frames, a
// silent pty, a missing path and a plain file — and a missing device's log
// line names the serial devices there are. Issue 41: it leaves alone a
// device another program has open or locked (gportd's own among them),
// and keeps settings someone else changed while it listened.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <sys/ioctl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "harness.hpp"

namespace gport::testing {
namespace {

// A pseudo-terminal whose slave is linked at `link` and open nowhere: the
// master holds it, and is another device. Its descriptor is not inherited.
struct FreePty {
    explicit FreePty(const std::string& link) {
        int slave = -1;
        EXPECT_EQ(::openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
        ::close(slave);
        ::fcntl(master, F_SETFD, FD_CLOEXEC);
        std::filesystem::create_symlink(::ptsname(master), link);
    }
    ~FreePty() { ::close(master); }
    FreePty(const FreePty&) = delete;
    FreePty& operator=(const FreePty&) = delete;
    int master = -1;
};

// A free pty (FreePty). A chattering one gets bytes that hold no valid
// G-Port frame (0xAE never starts one: every byte is below 0x80) every
// 20 ms; a flooding one as fast as they are read.
class Decoy {
  public:
    enum class Kind { kSilent, kChatter, kFlood };

    Decoy(const std::string& link, Kind kind) : pty_(link), master_(pty_.master) {
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
    }

  private:
    FreePty pty_;
    int master_ = -1;
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

// Reads a running probe's report to its end.
Probe finish(Process& process) {
    Probe p;
    while (auto line = process.next_line(30s)) {
        p.lines.push_back(*line);
    }
    p.status = process.wait(30s).value_or(-1);
    return p;
}

std::vector<std::string> probe_argv(std::vector<std::string> devices) {
    devices.insert(devices.begin(), {GPORTD_PATH, "--probe"});
    return devices;
}

Probe probe(std::vector<std::string> devices) {
    Process process(probe_argv(std::move(devices)));
    return finish(process);
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

// Issue 41: the probe never disturbs a device another program uses.

termios settings_of(int fd) {
    termios t{};
    EXPECT_EQ(::tcgetattr(fd, &t), 0) << std::strerror(errno);
    return t;
}

speed_t speed_of(int fd) {
    const auto t = settings_of(fd);
    return ::cfgetospeed(&t);
}

bool same_settings(const termios& a, const termios& b) {
    return a.c_iflag == b.c_iflag && a.c_oflag == b.c_oflag && a.c_cflag == b.c_cflag &&
           a.c_lflag == b.c_lflag && std::memcmp(a.c_cc, b.c_cc, sizeof a.c_cc) == 0 &&
           ::cfgetispeed(&a) == ::cfgetispeed(&b) && ::cfgetospeed(&a) == ::cfgetospeed(&b);
}

// An autopilot link's settings: 57600 raw with RTS/CTS, blocking reads.
void set_autopilot_line(int fd) {
    termios t = settings_of(fd);
    ::cfmakeraw(&t);
    t.c_cflag |= CRTSCTS | CLOCAL | CREAD;
    t.c_cc[VMIN] = 1;
    t.c_cc[VTIME] = 0;
    ASSERT_EQ(::cfsetspeed(&t, B57600), 0);
    ASSERT_EQ(::tcsetattr(fd, TCSANOW, &t), 0) << std::strerror(errno);
}

// Samples `fd`'s settings every 2 ms until destroyed; counts the samples
// that differ from those at the start.
class SettingsWatch {
  public:
    explicit SettingsWatch(int fd) : fd_(fd), first_(settings_of(fd)) {
        thread_ = std::thread([this] {
            while (!stop_) {
                changed_ += same_settings(settings_of(fd_), first_) ? 0 : 1;
                ++samples_;
                std::this_thread::sleep_for(2ms);
            }
        });
    }
    ~SettingsWatch() { finish(); }
    void finish() {
        stop_ = true;
        if (thread_.joinable()) {
            thread_.join();
        }
    }
    long changed() const { return changed_; }
    long samples() const { return samples_; }

  private:
    int fd_;
    termios first_;
    std::atomic<bool> stop_{false};
    std::atomic<long> changed_{0};
    std::atomic<long> samples_{0};
    std::thread thread_;
};

// 1,000 bytes a second into a pty's master (10 every 10 ms), and a reader
// on its slave that counts what arrives.
class Stream {
  public:
    Stream(int master, int slave) {
        writer_ = std::thread([this, master] {
            const std::array<unsigned char, 10> bytes{'m', 'a', 'v', 'l', 'i',
                                                      'n', 'k', '.', '.', '\n'};
            while (!stop_) {
                written_ += std::max<ssize_t>(::write(master, bytes.data(), bytes.size()), 0);
                std::this_thread::sleep_for(10ms);
            }
        });
        reader_ = std::thread([this, slave] {
            std::array<unsigned char, 4096> buffer{};
            while (!done_) {
                pollfd p{slave, POLLIN, 0};
                if (::poll(&p, 1, 50) > 0) {
                    received_ += std::max<ssize_t>(::read(slave, buffer.data(), buffer.size()), 0);
                }
            }
        });
    }
    ~Stream() { finish(); }
    // Stops writing and waits (up to 5 s) for the reader to have every byte.
    void finish() {
        stop_ = true;
        if (writer_.joinable()) {
            writer_.join();
        }
        eventually([this] { return received_ == written_; }, 5s);
        done_ = true;
        if (reader_.joinable()) {
            reader_.join();
        }
    }
    long written() const { return written_; }
    long received() const { return received_; }

  private:
    std::atomic<bool> stop_{false};
    std::atomic<bool> done_{false};
    std::atomic<long> written_{0};
    std::atomic<long> received_{0};
    std::thread writer_;
    std::thread reader_;
};

std::string comm_of(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/comm");
    std::string name;
    std::getline(in, name);
    return name;
}

TEST(Probe, LeavesALineAnotherProgramHasOpenAloneAndItsReaderGetsEveryByte) {
    TempDir dir;
    int master = -1;
    int slave = -1;
    ASSERT_EQ(::openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
    ::fcntl(master, F_SETFD, FD_CLOEXEC);
    ::fcntl(slave, F_SETFD, FD_CLOEXEC);
    std::filesystem::create_symlink(::ptsname(master), dir.file("autopilot"));
    set_autopilot_line(slave);
    Probe p;
    long written = 0;
    long received = 0;
    long changed = 0;
    long samples = 0;
    {
        SettingsWatch watch(slave);
        Stream stream(master, slave);
        const auto start = std::chrono::steady_clock::now();
        std::this_thread::sleep_for(500ms);
        p = probe({dir.file("autopilot")});
        std::this_thread::sleep_until(start + 3500ms);  // 3,500 bytes, as measured (issue 41)
        stream.finish();
        watch.finish();
        std::tie(written, received, changed, samples) =
            std::tuple(stream.written(), stream.received(), watch.changed(), watch.samples());
    }
    ::close(slave);
    ::close(master);
    EXPECT_NE(p.line_of(dir.file("autopilot"))
                  .find("in use by PID " + std::to_string(::getpid()) + " " + comm_of(::getpid()) +
                        ": left alone"),
              std::string::npos)
        << p.text();
    EXPECT_GE(written, 3000) << "1,000 B/s for 3.5 s";
    EXPECT_EQ(received, written) << "the probe took the holder's bytes";
    EXPECT_GT(samples, 100);
    EXPECT_EQ(changed, 0) << "of " << samples << " samples, the holder's settings differed in";
}

TEST(Probe, AFreeDeviceHasItsSettingsPutBack) {
    TempDir dir;
    FreePty pty(dir.file("free"));
    set_autopilot_line(pty.master);  // a pty's master sets its slave's settings
    const auto before = settings_of(pty.master);
    const auto p = probe({dir.file("free")});
    EXPECT_NE(p.line_of(dir.file("free")).find("silent (nothing received)"), std::string::npos)
        << p.text();
    EXPECT_EQ(p.text().find("left as they are"), std::string::npos) << p.text();
    EXPECT_TRUE(same_settings(settings_of(pty.master), before));
    // Its exclusive hold went with it (a pty's line outlives the probe's
    // close while the master is open): the next program opens it.
    const int fd = ::open(::ptsname(pty.master), O_RDWR | O_NOCTTY | O_CLOEXEC);
    ASSERT_GE(fd, 0) << std::strerror(errno);
    int exclusive = -1;
    EXPECT_EQ(::ioctl(fd, TIOCGEXCL, &exclusive), 0);
    EXPECT_EQ(exclusive, 0);
    ::close(fd);
}

// TIOCEXCL is the line's flag: root opens the line while the probe listens
// (TIOCEXCL does not stop root) and holds it exclusively for itself. When
// the probe lets go, another program still has the line open, and its
// exclusive hold stays.
TEST(Probe, AnExclusiveHoldTakenWhileItListensIsKept) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "only root opens a line the probe holds exclusively";
    }
    TempDir dir;
    FreePty pty(dir.file("radio"));
    Process process(probe_argv({dir.file("radio")}));
    ASSERT_TRUE(eventually([&] { return speed_of(pty.master) == B115200; }))
        << "the probe never set 115200";
    const int fd = ::open(::ptsname(pty.master), O_RDWR | O_NOCTTY | O_CLOEXEC);
    ASSERT_GE(fd, 0) << std::strerror(errno);
    ASSERT_EQ(::ioctl(fd, TIOCEXCL), 0);
    const auto p = finish(process);
    EXPECT_EQ(p.status, 1) << p.text();
    int exclusive = -1;
    EXPECT_EQ(::ioctl(fd, TIOCGEXCL, &exclusive), 0);
    EXPECT_EQ(exclusive, 1) << "the probe took the other program's exclusive hold away";
    ::close(fd);
}

// Ctrl-C (or a hang-up, or a kill) while it listens: a USB adapter's tty
// keeps its settings across closes, so dying at once would leave the next
// program 115200 raw. The listening stops, the settings are put back, the
// report says so, and then the signal ends the probe.
TEST(Probe, CtrlCWhileItListensPutsTheSettingsBackFirst) {
    TempDir dir;
    FreePty pty(dir.file("gps"));
    set_autopilot_line(pty.master);
    const auto before = settings_of(pty.master);
    Process process(probe_argv({dir.file("gps")}));
    ASSERT_TRUE(eventually([&] { return speed_of(pty.master) == B115200; }))
        << "the probe never set 115200";
    process.signal(SIGINT);
    const auto p = finish(process);
    EXPECT_EQ(p.status, 128 + SIGINT) << p.text();
    EXPECT_NE(p.text().find("interrupted (SIGINT): stopped listening, settings put back"),
              std::string::npos)
        << p.text();
    EXPECT_NE(p.line_of(dir.file("gps")).find("silent (nothing received)"), std::string::npos)
        << p.text();
    EXPECT_TRUE(same_settings(settings_of(pty.master), before)) << "the line was left 115200 raw";
}

TEST(Probe, SettingsSomeoneElseChangesWhileItListensAreKept) {
    TempDir dir;
    FreePty pty(dir.file("gps"));
    Process process(probe_argv({dir.file("gps")}));
    ASSERT_TRUE(eventually([&] { return speed_of(pty.master) == B115200; }))
        << "the probe never set 115200";
    // gpsd's autobaud, say: another speed, through the master.
    auto t = settings_of(pty.master);
    ASSERT_EQ(::cfsetspeed(&t, B57600), 0);
    ASSERT_EQ(::tcsetattr(pty.master, TCSANOW, &t), 0);
    const auto p = finish(process);
    EXPECT_EQ(speed_of(pty.master), B57600) << "the probe's restore undid it";
    EXPECT_NE(
        p.line_of(dir.file("gps"))
            .find("its settings were changed by another program while the probe listened: left "
                  "as they are"),
        std::string::npos)
        << p.text();
}

// Another process with the line open and exclusive (TIOCEXCL): root may
// open it all the same, so the probe must not even try.
TEST(Probe, LeavesALineHeldExclusivelyAlone) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "TIOCEXCL stops a user's open() itself; only root's probe could open it";
    }
    TempDir dir;
    FreePty pty(dir.file("radio"));
    const std::string slave_path = ::ptsname(pty.master);
    set_autopilot_line(pty.master);
    std::array<int, 2> ready{};
    ASSERT_EQ(::pipe(ready.data()), 0);
    const pid_t holder = ::fork();
    if (holder == 0) {
        ::prctl(PR_SET_NAME, "excl-holder");
        const int fd = ::open(slave_path.c_str(), O_RDWR | O_NOCTTY);
        if (fd < 0 || ::ioctl(fd, TIOCEXCL) != 0 || ::write(ready[1], "x", 1) != 1) {
            ::_exit(1);
        }
        ::pause();
        ::_exit(0);
    }
    char byte = 0;
    ASSERT_EQ(::read(ready[0], &byte, 1), 1);
    ::close(ready[0]);
    ::close(ready[1]);
    Probe p;
    long changed = 0;
    {
        SettingsWatch watch(pty.master);
        p = probe({dir.file("radio")});
        watch.finish();
        changed = watch.changed();
    }
    ::kill(holder, SIGKILL);
    ::waitpid(holder, nullptr, 0);
    EXPECT_NE(p.line_of(dir.file("radio"))
                  .find("in use by PID " + std::to_string(holder) + " excl-holder: left alone"),
              std::string::npos)
        << p.text();
    EXPECT_EQ(changed, 0) << "the holder's settings changed during the probe";
}

TEST(Probe, LeavesTheDeviceARunningGportdServesAloneAndItsLinkStaysUp) {
    TempDir dir;
    SimProcess sim(dir);
    DaemonProcess daemon(dir, {"--device", sim.link()});
    Client client(daemon.socket());
    ASSERT_TRUE(link_up(client));
    Client watch(daemon.socket());
    watch.call("subscribe", {{"topics", {"link"}}});
    const auto before = client.call("status")["result"];
    const auto start = std::chrono::steady_clock::now();
    const auto p = probe({sim.link()});
    std::this_thread::sleep_until(start + 2s);  // the 1.5 s the probe used to listen, and more
    const auto after = client.call("status")["result"];
    EXPECT_NE(p.line_of(sim.link())
                  .find("in use by PID " + std::to_string(daemon.process().pid()) +
                        " gportd: left alone (gportd serves it"),
              std::string::npos)
        << p.text();
    EXPECT_EQ(p.status, 1) << p.text();
    EXPECT_EQ(after["link"]["state"], "up") << after;
    EXPECT_EQ(after["counters"]["device_opens"], 1) << after;
    const auto frames = after["counters"]["attitude_frames"].get<long>() -
                        before["counters"]["attitude_frames"].get<long>();
    EXPECT_GT(frames, 60) << "attitude frames gportd got in the 2 s from the probe's start (~50 a "
                             "second)";
    EXPECT_FALSE(watch.notification("link", 300ms).has_value()) << "the link changed state";
}

// A UUCP lock file (minicom's, say) in /run/lock.
class LockFile {
  public:
    LockFile(const std::string& name, pid_t pid) : path_("/run/lock/LCK.." + name) {
        std::ofstream(path_) << std::setw(10) << pid << "\n";
    }
    ~LockFile() { std::filesystem::remove(path_); }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

TEST(Probe, AUucpLockOfALiveProcessKeepsItAwayAndAStaleOneIsLeftInPlace) {
    if (::access("/run/lock", W_OK) != 0) {
        GTEST_SKIP() << "/run/lock is not writable here: no lock file to make";
    }
    TempDir dir;
    const std::string name = "gport-probe-" + std::to_string(::getpid());
    FreePty pty(dir.file(name));
    Process holder({"/bin/sleep", "30"});
    LockFile lock(name, holder.pid());
    const auto held = probe({dir.file(name)});
    EXPECT_NE(held.line_of(dir.file(name))
                  .find("in use by PID " + std::to_string(holder.pid()) + " sleep (lock file " +
                        lock.path() + "): left alone"),
              std::string::npos)
        << held.text();
    holder.signal(SIGKILL);
    ASSERT_TRUE(holder.wait(5s).has_value());
    const auto stale = probe({dir.file(name)});
    EXPECT_NE(stale.line_of(dir.file(name)).find("silent (nothing received)"), std::string::npos)
        << stale.text();
    EXPECT_TRUE(std::filesystem::exists(lock.path())) << "a stale lock is ignored, never removed";
}

}  // namespace
}  // namespace gport::testing
