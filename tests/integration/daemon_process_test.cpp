// gportd as a process: its exit codes, the stop it sends on SIGTERM, the
// deadman for a killed client, and its systemd integration (sd_notify and
// socket activation) — with the real binaries, a pty and a real socket.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "harness.hpp"

namespace gport::testing {
namespace {

TEST(DaemonProcess, UsageErrorExits64) {
    Process p({GPORTD_PATH, "--no-such-option"});
    EXPECT_EQ(p.wait(), 64);
    Process missing({GPORTD_PATH, "--device"});
    EXPECT_EQ(missing.wait(), 64);
    Process positional({GPORTD_PATH, "/dev/ttyUSB0"});
    EXPECT_EQ(positional.wait(), 64);
}

TEST(DaemonProcess, ConfigErrorExits78BeforeTouchingTheGimbal) {
    TempDir dir;
    const auto path = dir.file("bad.json");
    std::ofstream(path) << R"({"keepalive": {"rate_hz": 1000}, "bogus": 1})";
    Process p({GPORTD_PATH, "--config", path, "--device", dir.file("never-opened")});
    EXPECT_EQ(p.wait(), 78);
}

// The non-root quick start: a user cannot create the socket (as for
// /run/gportd.sock); gportd exits 1 and says how to run without root, in a
// directory the user has: $XDG_RUNTIME_DIR, or $HOME where the login set
// none (su -), saying so.
TEST(DaemonProcess, SocketAUserMayNotCreateExits1WithTheNonRootWay) {
    TempDir dir;
    const std::string locked = dir.file("locked");
    ASSERT_EQ(::chmod(dir.path().c_str(), 0755), 0);
    ASSERT_EQ(::mkdir(locked.c_str(), 0555), 0);
    for (const bool runtime_dir : {true, false}) {
        // stderr into the captured stdout; as uid 65534 when we are root
        // (CI), for whom the directory's mode does not count.
        std::vector<std::string> argv{"/bin/sh", "-c", "exec \"$0\" \"$@\" 2>&1", "/usr/bin/env"};
        if (runtime_dir) {
            argv.push_back("XDG_RUNTIME_DIR=/run/user/65534");
        } else {
            argv.insert(argv.end(), {"-u", "XDG_RUNTIME_DIR"});
        }
        if (::geteuid() == 0) {
            argv.insert(argv.end(), {"/usr/bin/setpriv", "--reuid=65534", "--regid=65534",
                                     "--clear-groups", "--"});
        }
        argv.insert(argv.end(), {GPORTD_PATH, "--simulate", "--socket", locked + "/gportd.sock"});
        Process p(argv);
        std::string out;
        while (auto line = p.next_line()) {  // until gportd exits
            out += *line + "\n";
        }
        EXPECT_EQ(p.wait(), 1) << out;
        EXPECT_NE(out.find("cannot bind: Permission denied"), std::string::npos) << out;
        if (runtime_dir) {
            EXPECT_NE(out.find("--socket \"$XDG_RUNTIME_DIR/gportd.sock\""), std::string::npos)
                << out;
        } else {
            EXPECT_NE(out.find("--socket \"$HOME/gportd.sock\" (XDG_RUNTIME_DIR is not set"),
                      std::string::npos)
                << out;
        }
        EXPECT_NE(out.find("gport group"), std::string::npos) << out;
    }
}

TEST(DaemonProcess, HelpAndVersionExitZero) {
    Process help({GPORTD_PATH, "--help"});
    auto first = help.next_line();
    ASSERT_TRUE(first.has_value());
    EXPECT_NE(first->find("gportd"), std::string::npos);
    EXPECT_EQ(help.wait(), 0);
    Process version({GPORTD_PATH, "--version"});
    auto printed = version.next_line();
    ASSERT_TRUE(printed.has_value());
    EXPECT_EQ(printed->rfind("gportd ", 0), 0U) << *printed;
    EXPECT_EQ(version.wait(), 0);
}

TEST(DaemonProcess, SigtermStopsRunningMotionBeforeExit) {
    TempDir dir;
    SimProcess sim(dir);
    DaemonProcess daemon(dir, {"--device", sim.link()});
    Client client(daemon.socket());
    ASSERT_TRUE(client.connected());
    ASSERT_TRUE(link_up(client));
    auto reply = client.call("speed", {{"yaw", 20}, {"duration_ms", 30000}});
    ASSERT_TRUE(reply.contains("result")) << reply.dump();
    ASSERT_TRUE(sim.wait_speed({0, 0, 2000}));
    daemon.process().signal(SIGTERM);
    EXPECT_TRUE(sim.wait_speed({0, 0, 0})) << "no zero-speed frame after SIGTERM";
    EXPECT_EQ(daemon.process().wait(), 0);
}

TEST(DaemonProcess, KilledClientMidMotionIsStopped) {
    TempDir dir;
    SimProcess sim(dir);
    DaemonProcess daemon(dir, {"--device", sim.link()});
    Client watcher(daemon.socket());
    ASSERT_TRUE(link_up(watcher));
    watcher.call("subscribe", {{"topics", {"motion"}}});
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        Client c(daemon.socket());
        c.call("speed", {{"pitch", 10}, {"duration_ms", 30000}});
        ::pause();
        ::_exit(0);
    }
    ASSERT_TRUE(sim.wait_speed({0, 1000, 0}));
    ::kill(child, SIGKILL);
    ::waitpid(child, nullptr, 0);
    EXPECT_TRUE(sim.wait_speed({0, 0, 0})) << "the deadman did not stop the gimbal";
    bool owner_gone = false;
    while (auto n = watcher.notification("motion", 5s)) {
        if ((*n)["params"].value("reason", "") == "owner_gone") {
            owner_gone = true;
            break;
        }
    }
    EXPECT_TRUE(owner_gone);
}

TEST(DaemonProcess, SecondDaemonOnALiveSocketRefusesToStart) {
    TempDir dir;
    DaemonProcess first(dir, {"--simulate"});
    Client c(first.socket());
    ASSERT_TRUE(c.connected());
    Process second({GPORTD_PATH, "--simulate", "--socket", first.socket()});
    auto status = second.wait();
    ASSERT_TRUE(status.has_value());
    EXPECT_NE(*status, 0);
    // The second daemon's probe of the socket is a client too, until the
    // first daemon has seen it close.
    EXPECT_TRUE(eventually([&] { return c.call("status")["result"]["clients"] == 1; }))
        << "the first daemon is unharmed";
}

// A datagram socket owned by the test, given to gportd as NOTIFY_SOCKET.
class NotifySocket {
  public:
    explicit NotifySocket(const std::string& path) : path_(path) {
        fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        sockaddr_un addr{};
        addr.sun_family = AF_UNIX;
        std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
        ::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
        timeval tv{0, 200000};
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    }
    ~NotifySocket() { ::close(fd_); }

    // Collects messages until one contains `what`, or the timeout.
    bool wait_for(const std::string& what, std::chrono::milliseconds timeout = 10s) {
        return eventually(
            [&] {
                char buf[4096];
                const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
                if (n > 0) {
                    seen_.append(buf, static_cast<std::size_t>(n)).push_back('\n');
                }
                return seen_.find(what) != std::string::npos;
            },
            timeout);
    }
    const std::string& seen() const { return seen_; }

  private:
    std::string path_;
    std::string seen_;
    int fd_ = -1;
};

TEST(DaemonProcess, NotifiesReadyStatusWatchdogAndStopping) {
    TempDir dir;
    NotifySocket notify(dir.file("notify"));
    DaemonProcess daemon(dir, {"--simulate"},
                         {"NOTIFY_SOCKET=" + dir.file("notify"), "WATCHDOG_USEC=400000"});
    EXPECT_TRUE(notify.wait_for("READY=1")) << notify.seen();
    EXPECT_TRUE(notify.wait_for("STATUS=")) << notify.seen();
    EXPECT_TRUE(notify.wait_for("link up")) << notify.seen();
    EXPECT_TRUE(notify.wait_for("WATCHDOG=1")) << notify.seen();
    daemon.process().signal(SIGTERM);
    EXPECT_TRUE(notify.wait_for("STOPPING=1")) << notify.seen();
    EXPECT_EQ(daemon.process().wait(), 0);
}

TEST(DaemonProcess, NoWatchdogPingsWithoutWatchdogUsec) {
    TempDir dir;
    NotifySocket notify(dir.file("notify"));
    DaemonProcess daemon(dir, {"--simulate"}, {"NOTIFY_SOCKET=" + dir.file("notify")});
    ASSERT_TRUE(notify.wait_for("READY=1"));
    notify.wait_for("never", 1s);
    EXPECT_EQ(notify.seen().find("WATCHDOG=1"), std::string::npos);
}

TEST(DaemonProcess, ServesClientsOnASocketPassedBySystemd) {
    TempDir dir;
    const auto path = dir.file("activated.sock");
    // systemd-socket-activate passes on only the variables it is told to:
    // under qemu-user (a cross build's tests) gportd needs QEMU_LD_PREFIX.
    std::vector<std::string> argv{"/usr/bin/systemd-socket-activate", "-l", path};
    if (std::getenv("QEMU_LD_PREFIX") != nullptr) {
        argv.insert(argv.end(), {"-E", "QEMU_LD_PREFIX"});
    }
    argv.insert(argv.end(), {GPORTD_PATH, "--simulate", "--config", write_test_config(dir),
                             "--socket", dir.file("unused.sock")});
    Process activator(argv);
    Client client(path);
    ASSERT_TRUE(client.connected());
    auto reply = client.call("status");
    ASSERT_TRUE(reply.contains("result")) << reply.dump();
    EXPECT_FALSE(std::ifstream(dir.file("unused.sock")).good())
        << "the passed socket takes precedence over the configured path";
}

}  // namespace
}  // namespace gport::testing
