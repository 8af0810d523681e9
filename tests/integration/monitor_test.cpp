// gportctl monitor as a person sees it: the real gportctl in a real terminal
// (tmux, 80×24) against the real gportd, on --simulate or on gport-sim;
// assertions on what capture-pane shows. Plus the plain mode, when stdout is
// not a terminal.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <regex>
#include <sstream>

#include "harness.hpp"
#include "tmux_pane.hpp"

namespace gport::testing {
namespace {

// The IMU yaw the screen shows ("IMU     +12.34°  -30.00°  +45.00°").
std::optional<double> screen_imu_yaw(const std::string& screen) {
    static const std::regex kImu(R"(IMU +([-+][0-9.]+)° +([-+][0-9.]+)° +([-+][0-9.]+)°)");
    std::smatch match;
    if (!std::regex_search(screen, match, kImu)) {
        return std::nullopt;
    }
    return std::stod(match[3].str());
}

// The pane's command: the monitor, then its exit status and the terminal's
// modes, kept on screen.
std::string monitor_command(const std::string& socket, const std::string& options) {
    return fmt::format("{} --socket {} monitor {}; echo MONITOR-EXIT=$?; stty -a; sleep 60",
                       GPORTCTL_PATH, socket, options);
}

class Monitor : public ::testing::Test {
  protected:
    void SetUp() override {
        ASSERT_TRUE(shell_output("tmux -V").has_value())
            << "tmux is not installed; scripts/deps.sh installs it (Debian package tmux)";
    }

    // gportd --simulate with the link up.
    void start_simulated_daemon() {
        daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"});
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
    }

    TempDir dir_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> client_;
};

TEST_F(Monitor, AnglesChangeWhileASpeedRunsAndTheTerminalIsRestored) {
    start_simulated_daemon();
    TmuxPane pane(dir_, monitor_command(daemon_->socket(), "--for 8s"));
    ASSERT_TRUE(pane.started());
    std::string screen;
    ASSERT_TRUE(pane.wait_screen(
        [](const std::string& s) {
            return contains(s, "● UP") && screen_imu_yaw(s) && contains(s, "q quit");
        },
        screen))
        << screen;
    EXPECT_TRUE(contains(screen, "gportctl monitor · gportd")) << screen;
    EXPECT_TRUE(contains(screen, "hall ")) << screen;
    EXPECT_EQ(pane.format("#{alternate_on}"), "1");
    const double yaw_before = *screen_imu_yaw(screen);

    Process speed(
        {GPORTCTL_PATH, "--socket", daemon_->socket(), "speed", "--yaw", "40", "--for", "1500ms"});
    EXPECT_TRUE(pane.wait_screen(
        [](const std::string& s) {
            return contains(s, "speed   yaw +40.0 °/s") && contains(s, "speed started by");
        },
        screen))
        << screen;
    EXPECT_TRUE(pane.wait_screen(
        [&](const std::string& s) {
            auto yaw = screen_imu_yaw(s);
            return yaw && *yaw > yaw_before + 10;
        },
        screen))
        << "yaw before " << yaw_before << ", now:\n"
        << screen;
    EXPECT_EQ(speed.wait(), 0);
    EXPECT_TRUE(pane.wait_screen(
        [](const std::string& s) { return contains(s, "speed: duration at"); }, screen))
        << screen;

    // --for ends it; the terminal is as it was: normal screen, cursor shown,
    // canonical mode with echo.
    ASSERT_TRUE(pane.wait_screen(
        [](const std::string& s) { return contains(s, "MONITOR-EXIT=0") && contains(s, "icanon"); },
        screen, 15s))
        << screen;
    EXPECT_FALSE(contains(screen, "gportctl monitor ·")) << screen;
    EXPECT_EQ(pane.format("#{alternate_on} #{cursor_flag}"), "0 1");
    EXPECT_TRUE(std::regex_search(screen, std::regex(R"((^|\s)icanon(\s|$))"))) << screen;
    EXPECT_TRUE(std::regex_search(screen, std::regex(R"((^|\s)echo(\s|$))"))) << screen;
}

TEST_F(Monitor, LinkDownShowsWhenTheDeviceVanishesWithoutColourUnderNoColor) {
    SimProcess sim(dir_);
    DaemonProcess daemon(dir_, {"--device", sim.link()});
    Client client(daemon.socket());
    ASSERT_TRUE(link_up(client));
    TmuxPane pane(dir_, monitor_command(daemon.socket(), ""), {"NO_COLOR=1"});
    ASSERT_TRUE(pane.started());
    std::string screen;
    ASSERT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "● UP"); }, screen))
        << screen;
    // NO_COLOR: the cells carry no colour (tmux would print SGR codes for them).
    const std::string with_escapes = pane.screen(true);
    EXPECT_FALSE(std::regex_search(with_escapes, std::regex("\x1b\\[[0-9;]*m"))) << with_escapes;

    sim.process().signal(SIGKILL);
    EXPECT_TRUE(pane.wait_screen(
        [](const std::string& s) { return contains(s, "● DOWN") && contains(s, "link down"); },
        screen))
        << screen;

    pane.keys("q");  // q quits at once, long before any --for
    EXPECT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "MONITOR-EXIT=0"); },
                                 screen))
        << screen;
}

TEST_F(Monitor, WithControlTheArrowsNudgeAndControlIsReleasedOnExit) {
    start_simulated_daemon();
    TmuxPane pane(dir_, monitor_command(daemon_->socket(), "--control"));
    ASSERT_TRUE(pane.started());
    std::string screen;
    ASSERT_TRUE(pane.wait_screen(
        [](const std::string& s) { return contains(s, "control: you") && screen_imu_yaw(s); },
        screen))
        << screen;
    EXPECT_NE(client_->call("status")["result"]["controller"], nullptr);
    pane.keys("Right");
    EXPECT_TRUE(pane.wait_screen(
        [](const std::string& s) { return contains(s, "speed started by you: yaw +20.0 °/s"); },
        screen))
        << screen;
    pane.keys("c");
    EXPECT_TRUE(
        pane.wait_screen([](const std::string& s) { return contains(s, "centre sent"); }, screen))
        << screen;
    pane.keys("C-c");  // Ctrl-C quits too, with the terminal restored
    ASSERT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "MONITOR-EXIT=0"); },
                                 screen))
        << screen;
    EXPECT_EQ(pane.format("#{alternate_on}"), "0");
    EXPECT_TRUE(
        eventually([&] { return client_->call("status")["result"]["controller"].is_null(); }));
}

TEST_F(Monitor, PlainStatusBlocksWhenStdoutIsNotATerminal) {
    start_simulated_daemon();
    Process monitor({GPORTCTL_PATH, "--socket", daemon_->socket(), "monitor", "--for", "2500ms"},
                    {"LC_ALL=C.UTF-8"});
    std::vector<std::string> lines;
    while (auto line = monitor.next_line()) {
        lines.push_back(*line);
    }
    EXPECT_EQ(monitor.wait(), 0);
    int blocks = 0;
    bool link_up_line = false;
    for (const auto& line : lines) {
        EXPECT_FALSE(contains(line, "\x1b")) << line;
        blocks += line.rfind("gportctl monitor ", 0) == 0 ? 1 : 0;
        link_up_line = link_up_line || contains(line, "link ● UP");
    }
    EXPECT_GE(blocks, 2);
    EXPECT_TRUE(link_up_line);
}

// The first row of the screen that contains `text`, or "".
std::string row_with(const std::string& screen, const std::string& text) {
    std::istringstream rows(screen);
    for (std::string row; std::getline(rows, row);) {
        if (contains(row, text)) {
            return row;
        }
    }
    return "";
}

TEST_F(Monitor, At80ColumnsALongSocketNameKeepsItsFileNameUptimeAndClock) {
    start_simulated_daemon();
    // A multi-gimbal name in a deep directory: a link to the daemon's socket.
    const std::string dir = dir_.file("run-gport-site-a-long-directory-name");
    ASSERT_EQ(::mkdir(dir.c_str(), 0700), 0);
    const std::string socket = dir + "/gportd-gimbal1.sock";
    ASSERT_EQ(::symlink(daemon_->socket().c_str(), socket.c_str()), 0);
    ASSERT_GT(socket.size() + 40, 80U) << "the path alone must not fit the title";
    TmuxPane pane(dir_, monitor_command(socket, ""));
    ASSERT_TRUE(pane.started());
    std::string screen;
    ASSERT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "● UP"); }, screen))
        << screen;
    const std::string title = row_with(screen, "gportctl monitor");
    EXPECT_TRUE(std::regex_search(
        title, std::regex(R"(^ gportctl monitor · gportd \S+ · …/gportd-gimbal1\.sock +)"
                          R"(up [0-9.]+ s  [0-9]{2}:[0-9]{2}:[0-9]{2}$)")))
        << title;
    pane.keys("q");
    EXPECT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "MONITOR-EXIT=0"); },
                                 screen))
        << screen;
}

TEST_F(Monitor, AfterTheDaemonDiesItsLastValuesAreMarkedStaleAndTheReasonIsWhole) {
    start_simulated_daemon();
    ASSERT_EQ(client_->call("record", {{"on", true}, {"force", true}})["result"].is_object(), true);
    TmuxPane pane(dir_, monitor_command(daemon_->socket(), ""));
    ASSERT_TRUE(pane.started());
    std::string screen;
    ASSERT_TRUE(pane.wait_screen(
        [](const std::string& s) { return screen_imu_yaw(s) && contains(s, "rec on"); }, screen))
        << screen;
    client_.reset();
    daemon_->process().signal(SIGKILL);
    ASSERT_TRUE(daemon_->process().wait().has_value());
    ::unlink(daemon_->socket().c_str());  // as the issue saw it: "No such fi"
    ASSERT_TRUE(pane.wait_screen(
        [](const std::string& s) {
            return contains(s, "NOT CONNECTED") && contains(s, "reason") &&
                   contains(s, "running?)");
        },
        screen))
        << screen;
    // The values are still there, under titles that say they are stale...
    EXPECT_TRUE(screen_imu_yaw(screen)) << screen;
    EXPECT_TRUE(contains(screen, "rec on")) << screen;
    EXPECT_TRUE(contains(screen, "Angles · stale")) << screen;
    EXPECT_TRUE(contains(screen, "Daemon · stale")) << screen;
    EXPECT_TRUE(contains(screen, "Attitude (IMU) · stale")) << screen;
    // ... and faint: the last attributes tmux sets before them (capture-pane
    // carries attributes from row to row) include 2 (faint), not cleared
    // since (0 or 22).
    const std::string with_escapes = pane.screen(true);
    for (const std::string text : {"IMU ", "clients"}) {
        const std::string before = with_escapes.substr(0, with_escapes.find(text));
        const auto faint = before.rfind("\x1b[2m");
        ASSERT_NE(faint, std::string::npos) << text << ": " << with_escapes;
        EXPECT_EQ(before.find("\x1b[0m", faint), std::string::npos) << text << ": " << before;
        EXPECT_EQ(before.find("\x1b[22m", faint), std::string::npos) << text << ": " << before;
    }
    // The reason whole: the socket's path, then why, on rows of their own.
    std::string reason;
    for (std::istringstream rows(screen); std::getline(rows, reason);) {
        if (contains(reason, "reason")) {
            std::string next;
            while (std::getline(rows, next) && next.rfind("         ", 0) == 0) {
                reason += next;
            }
            break;
        }
    }
    std::string reason_text = reason;
    std::erase(reason_text, ' ');
    EXPECT_TRUE(
        contains(reason_text, daemon_->socket() + ":Nosuchfileordirectory(isgportdrunning?)"))
        << screen;
    pane.keys("q");
    EXPECT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "MONITOR-EXIT=0"); },
                                 screen))
        << screen;
}

TEST_F(Monitor, InTheCLocaleEverythingIsAscii) {
    start_simulated_daemon();
    TmuxPane pane(dir_, monitor_command(daemon_->socket(), ""), {"LANG=C", "LC_ALL=", "LC_CTYPE="});
    ASSERT_TRUE(pane.started());
    std::string screen;
    // "link UP" comes with the first frame, the angles with the first
    // attitude sample a little later: wait for both.
    const std::regex imu_value(R"(IMU +[-+][0-9.]+d)");
    ASSERT_TRUE(pane.wait_screen(
        [&](const std::string& s) {
            return contains(s, "link * UP") && contains(s, "q quit") &&
                   std::regex_search(s, imu_value);
        },
        screen))
        << screen;
    EXPECT_TRUE(contains(screen, "gportctl monitor - gportd")) << screen;
    EXPECT_TRUE(contains(screen, "+- Attitude (IMU) ---")) << screen;
    for (unsigned char c : screen) {
        ASSERT_LT(c, 0x80) << screen;
    }
    pane.keys("q");
    EXPECT_TRUE(pane.wait_screen([](const std::string& s) { return contains(s, "MONITOR-EXIT=0"); },
                                 screen))
        << screen;
}

TEST_F(Monitor, AsciiForcedInAUtf8Locale) {
    start_simulated_daemon();
    TmuxPane pane(dir_, monitor_command(daemon_->socket(), "--ascii --for 5s"));
    ASSERT_TRUE(pane.started());
    std::string screen;
    ASSERT_TRUE(pane.wait_screen(
        [](const std::string& s) { return contains(s, "link * UP") && contains(s, "q quit"); },
        screen))
        << screen;
    for (unsigned char c : screen) {
        ASSERT_LT(c, 0x80) << screen;
    }
}

TEST_F(Monitor, NoDaemonIsExit69) {
    Process monitor({GPORTCTL_PATH, "--socket", dir_.file("none.sock"), "monitor"});
    EXPECT_EQ(monitor.wait(), 69);
}

}  // namespace
}  // namespace gport::testing
