// SIGHUP's two meanings (docs/operations.md, "Reloading the configuration"):
// a gportd started from a terminal ends when that terminal hangs up, as
// every foreground program does, so the next start finds no daemon on the
// socket; `kill -HUP` while the terminal is open still reloads, and so does
// every SIGHUP under nohup (and under systemd, where there is no terminal:
// signals_test.cpp). gportd runs here as the session leader of a
// pseudo-terminal (forkpty), as a login shell's job would.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <thread>

#include "harness.hpp"

namespace gport::testing {
namespace {

// gportd --simulate on a terminal of its own, whose output is read all along
// (a terminal nobody reads would block its log lines).
class TerminalDaemon {
  public:
    TerminalDaemon(const TempDir& dir, bool nohup) : socket_(dir.file("gportd.sock")) {
        pid_ = ::forkpty(&master_, nullptr, nullptr, nullptr);
        if (pid_ == 0) {
            if (nohup) {
                ::signal(SIGHUP, SIG_IGN);
            }
            ::execl(GPORTD_PATH, GPORTD_PATH, "--simulate", "--socket", socket_.c_str(),
                    static_cast<char*>(nullptr));
            ::_exit(127);
        }
        reader_ = std::thread([this] { drain(); });
    }
    ~TerminalDaemon() {
        if (pid_ > 0 && !exited_) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
        close_terminal();
    }
    TerminalDaemon(const TerminalDaemon&) = delete;
    TerminalDaemon& operator=(const TerminalDaemon&) = delete;

    bool started() const { return pid_ > 0 && master_ >= 0; }
    pid_t pid() const { return pid_; }
    const std::string& socket() const { return socket_; }

    // Whether the terminal showed `what` within the timeout.
    bool shown(const std::string& what, std::chrono::milliseconds timeout = 20s) {
        return eventually(
            [&] {
                std::lock_guard lock(mutex_);
                return contains(screen_, what);
            },
            timeout);
    }
    std::string screen() {
        std::lock_guard lock(mutex_);
        return screen_;
    }

    // The terminal closes (its window, an SSH session): the kernel hangs it up.
    void close_terminal() {
        stop_ = true;
        if (reader_.joinable()) {
            reader_.join();
        }
        if (master_ >= 0) {
            ::close(master_);
            master_ = -1;
        }
    }

    // Its exit status once it ended within the timeout.
    std::optional<int> wait_exit(std::chrono::milliseconds timeout) {
        int status = 0;
        const bool ended =
            eventually([&] { return ::waitpid(pid_, &status, WNOHANG) == pid_; }, timeout);
        if (!ended) {
            return std::nullopt;
        }
        exited_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }

  private:
    void drain() {
        std::array<char, 4096> buffer{};
        while (!stop_) {
            pollfd p{master_, POLLIN, 0};
            if (::poll(&p, 1, 50) <= 0) {
                continue;
            }
            const auto n = ::read(master_, buffer.data(), buffer.size());
            if (n <= 0) {
                std::this_thread::sleep_for(10ms);  // the child ended: EIO until we close
                continue;
            }
            std::lock_guard lock(mutex_);
            screen_.append(buffer.data(), static_cast<std::size_t>(n));
        }
    }

    std::string socket_;
    int master_ = -1;
    pid_t pid_ = -1;
    bool exited_ = false;
    std::atomic<bool> stop_{false};
    std::mutex mutex_;
    std::string screen_;
    std::thread reader_;
};

TEST(Hangup, ClosingTheTerminalEndsGportdAndTheNextStartServes) {
    TempDir dir;
    TerminalDaemon daemon(dir, false);
    ASSERT_TRUE(daemon.started());
    ASSERT_TRUE(daemon.shown("ready")) << daemon.screen();
    EXPECT_TRUE(daemon.shown("started from a terminal: gportd ends when it hangs up"))
        << daemon.screen();
    daemon.close_terminal();
    const auto status = daemon.wait_exit(20s);
    ASSERT_TRUE(status.has_value()) << "gportd outlived its terminal";
    EXPECT_EQ(*status, 0);
    EXPECT_FALSE(std::filesystem::exists(daemon.socket())) << "its socket stayed behind";
    // The next start is not told that another daemon is listening.
    DaemonProcess next(dir, {"--simulate"});  // on the same socket path
    Client client(daemon.socket());
    ASSERT_TRUE(client.connected());
    EXPECT_TRUE(client.call("status").contains("result"));
}

TEST(Hangup, KillHupWhileTheTerminalIsOpenReloads) {
    TempDir dir;
    TerminalDaemon daemon(dir, false);
    ASSERT_TRUE(daemon.started());
    ASSERT_TRUE(daemon.shown("ready")) << daemon.screen();
    ASSERT_EQ(::kill(daemon.pid(), SIGHUP), 0);
    EXPECT_TRUE(daemon.shown("reload")) << daemon.screen();
    EXPECT_FALSE(daemon.wait_exit(500ms).has_value()) << daemon.screen();
    Client client(daemon.socket());
    ASSERT_TRUE(client.connected());
    EXPECT_TRUE(client.call("status").contains("result"));
}

TEST(Hangup, UnderNohupClosingTheTerminalLeavesItRunning) {
    TempDir dir;
    TerminalDaemon daemon(dir, true);
    ASSERT_TRUE(daemon.started());
    ASSERT_TRUE(daemon.shown("ready")) << daemon.screen();
    EXPECT_FALSE(contains(daemon.screen(), "started from a terminal")) << daemon.screen();
    daemon.close_terminal();
    EXPECT_FALSE(daemon.wait_exit(1s).has_value()) << "nohup asked it to survive the hang-up";
    Client client(daemon.socket());
    ASSERT_TRUE(client.connected());
    EXPECT_TRUE(client.call("status").contains("result"));
}

}  // namespace
}  // namespace gport::testing
