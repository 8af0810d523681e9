// The gport-sim executable, spawned as a user or an integration test would.
#include <fcntl.h>
#include <grp.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "gport/protocol/messages.hpp"

namespace {

using namespace std::chrono_literals;
namespace p = gport::protocol;

// A child process with its stdout and stderr on pipes.
class Child {
  public:
    explicit Child(std::vector<std::string> args) {
        int out[2];
        int err[2];
        if (::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0) {
            return;
        }
        pid_ = ::fork();
        if (pid_ == 0) {
            ::dup2(out[1], 1);
            ::dup2(err[1], 2);
            std::vector<char*> argv{const_cast<char*>(GPORT_SIM_BINARY)};
            for (auto& a : args) {
                argv.push_back(a.data());
            }
            argv.push_back(nullptr);
            ::execv(GPORT_SIM_BINARY, argv.data());
            ::_exit(127);
        }
        ::close(out[1]);
        ::close(err[1]);
        out_ = out[0];
        err_ = err[0];
    }
    ~Child() {
        if (pid_ > 0 && !status_) {
            ::kill(pid_, SIGKILL);
            wait();
        }
        ::close(out_);
        ::close(err_);
    }

    // The next stdout line, or nullopt after `timeout`.
    std::optional<std::string> line(std::chrono::milliseconds timeout = 5000ms) {
        const auto end = std::chrono::steady_clock::now() + timeout;
        for (;;) {
            if (const auto nl = out_buf_.find('\n'); nl != std::string::npos) {
                std::string l = out_buf_.substr(0, nl);
                out_buf_.erase(0, nl + 1);
                return l;
            }
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                end - std::chrono::steady_clock::now());
            pollfd pfd{out_, POLLIN, 0};
            if (left <= 0ms || ::poll(&pfd, 1, static_cast<int>(left.count())) <= 0) {
                return std::nullopt;
            }
            char buf[4096];
            const auto n = ::read(out_, buf, sizeof buf);
            if (n <= 0) {
                return std::nullopt;
            }
            out_buf_.append(buf, static_cast<std::size_t>(n));
        }
    }
    std::string all_stderr() {
        std::string s;
        char buf[4096];
        ssize_t n = 0;
        while ((n = ::read(err_, buf, sizeof buf)) > 0) {
            s.append(buf, static_cast<std::size_t>(n));
        }
        return s;
    }
    void signal(int sig) { ::kill(pid_, sig); }
    // Exit status (or 128 + signal).
    int wait() {
        if (!status_) {
            int st = 0;
            ::waitpid(pid_, &st, 0);
            status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
        }
        return *status_;
    }

  private:
    pid_t pid_ = -1;
    int out_ = -1;
    int err_ = -1;
    std::string out_buf_;
    std::optional<int> status_;
};

std::string link_path() {
    return (std::filesystem::temp_directory_path() /
            ("gport-sim-tool." + std::to_string(::getpid())))
        .string();
}

TEST(GportSimTool, HelpExplainsEveryOptionAndExitsZero) {
    Child c({"--help"});
    std::string help;
    while (auto l = c.line()) {
        help += *l + "\n";
    }
    EXPECT_EQ(c.wait(), 0);
    EXPECT_NE(help.find("Usage: gport-sim"), std::string::npos);
    EXPECT_NE(help.find("--vanish-every MS"), std::string::npos);
    EXPECT_NE(help.find("(default 50)"), std::string::npos);
}

TEST(GportSimTool, VersionExitsZero) {
    Child c({"--version"});
    const auto line = c.line();
    EXPECT_EQ(c.wait(), 0);
    ASSERT_TRUE(line.has_value());
    EXPECT_EQ(line->rfind("gport-sim ", 0), 0U) << *line;
}

TEST(GportSimTool, AnUnknownOptionIsRefusedWithoutTakingTheNextArgument) {
    Child c({"--verbose", "--rate", "5"});
    EXPECT_EQ(c.wait(), 64);
    EXPECT_NE(c.all_stderr().find("unknown option --verbose; the options are"), std::string::npos);
}

TEST(GportSimTool, ABadOptionIsAUsageErrorWithAClearMessage) {
    Child c({"--rate", "-3"});
    EXPECT_EQ(c.wait(), 64);
    const auto err = c.all_stderr();
    EXPECT_NE(err.find("--rate: -3: expected frames per second from 0 to 10000"), std::string::npos)
        << err;
}

// As udev makes an adapter root:dialout 0660: here our own primary group,
// which an unprivileged test may give its own pty (root may give any).
TEST(GportSimTool, GroupAndModeAreSetOnTheSlave) {
    const group* g = ::getgrgid(::getgid());
    ASSERT_NE(g, nullptr);
    Child c({"--group", g->gr_name, "--mode", "0640"});
    const auto slave = c.line();
    ASSERT_TRUE(slave.has_value());
    struct stat st {};
    ASSERT_EQ(::stat(slave->c_str(), &st), 0);
    EXPECT_EQ(st.st_gid, ::getgid());
    EXPECT_EQ(st.st_mode & 0777U, 0640U);
    // Its exit status is not this test's: a SIGTERM this soon after the
    // first line may come before its handler (143 under qemu, once).
    c.signal(SIGTERM);
    c.wait();
}

TEST(GportSimTool, AnUnknownGroupOrABadModeIsAUsageError) {
    Child nogroup({"--group", "no-such-group-here"});
    EXPECT_EQ(nogroup.wait(), 64);
    EXPECT_NE(nogroup.all_stderr().find("--group no-such-group-here: no such group"),
              std::string::npos)
        << nogroup.all_stderr();
    for (const char* mode : {"660x", "0", "1777", "rw-rw----"}) {
        Child bad({"--mode", mode});
        EXPECT_EQ(bad.wait(), 64) << mode;
        EXPECT_NE(bad.all_stderr().find("must be octal permission bits from 0001 to 0777"),
                  std::string::npos)
            << bad.all_stderr();
    }
}

TEST(GportSimTool, AnUnreadableRecordingIsReported) {
    Child c({"--replay", "/nonexistent/recording"});
    EXPECT_EQ(c.wait(), 66);
    EXPECT_NE(c.all_stderr().find("cannot open recording"), std::string::npos);
}

TEST(GportSimTool, ServesTheLinkTracesCommandsAndCleansUpOnSigterm) {
    const auto link = link_path();
    Child c({"--link", link, "--trace"});
    const auto slave = c.line();
    ASSERT_TRUE(slave.has_value());
    EXPECT_EQ(slave->rfind("/dev/pts/", 0), 0U);
    EXPECT_EQ(std::filesystem::read_symlink(link).string(), *slave);

    const int fd = ::open(link.c_str(), O_RDWR | O_NOCTTY);
    ASSERT_GE(fd, 0);
    const auto frame = p::encode(p::Control::speed_of({0, 0, 3000}));
    // The sim notices the open within one housekeeping tick; send after it.
    std::optional<std::string> l;
    bool opened = false;
    while (!opened && (l = c.line())) {
        opened = l->find("\"event\":\"peer_open\"") != std::string::npos;
    }
    ASSERT_TRUE(opened);
    ASSERT_EQ(::write(fd, frame.bytes().data(), frame.size()), static_cast<ssize_t>(frame.size()));
    bool traced = false;
    while (!traced && (l = c.line())) {
        traced = l->find(
                     "\"cmd\":\"0x85\",\"mode\":\"speed\",\"speed\":[0,0,3000],"
                     "\"angle\":[0,0,0]}") != std::string::npos &&
                 l->rfind("{\"t_ms\":", 0) == 0;
    }
    EXPECT_TRUE(traced);
    ::close(fd);

    c.signal(SIGTERM);
    EXPECT_EQ(c.wait(), 0);
    struct stat st {};
    EXPECT_NE(::lstat(link.c_str(), &st), 0) << "link left behind";
}

}  // namespace
