// Notifier and WatchdogDriver against a test-owned NOTIFY_SOCKET.
#include "gport/systemd/notifier.hpp"

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstring>
#include <optional>
#include <string>

#include "gport/systemd/watchdog.hpp"
#include "test_fds.hpp"

namespace gport::systemd {
namespace {

using namespace std::chrono_literals;
using test::EnvOverride;

// Generous: the machine is shared and noisy; a passing test never waits this long.
constexpr auto kPatience = 10s;

// The systemd side of sd_notify: a datagram socket bound to a temporary path.
class NotifySocket {
  public:
    NotifySocket() {
        char dir_template[] = "/tmp/gport-notify-XXXXXX";
        dir_ = mkdtemp(dir_template);
        path_ = dir_ + "/notify";
        fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        std::strncpy(address.sun_path, path_.c_str(), sizeof address.sun_path - 1);
        if (bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
            ADD_FAILURE() << "bind " << path_ << ": " << std::strerror(errno);
        }
    }
    ~NotifySocket() {
        close(fd_);
        unlink(path_.c_str());
        rmdir(dir_.c_str());
    }
    NotifySocket(const NotifySocket&) = delete;
    NotifySocket& operator=(const NotifySocket&) = delete;

    [[nodiscard]] const std::string& path() const { return path_; }

    // The next datagram, or std::nullopt if none arrives within `timeout`.
    std::optional<std::string> receive(std::chrono::milliseconds timeout) const {
        pollfd p{fd_, POLLIN, 0};
        if (poll(&p, 1, static_cast<int>(timeout.count())) != 1) {
            return std::nullopt;
        }
        char buffer[4096];
        const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
        if (n < 0) {
            return std::nullopt;
        }
        return std::string(buffer, static_cast<std::size_t>(n));
    }

  private:
    std::string dir_;
    std::string path_;
    int fd_ = -1;
};

class NotifierTest : public ::testing::Test {
  protected:
    NotifySocket systemd;
    EnvOverride notify_socket{"NOTIFY_SOCKET", systemd.path()};
    EnvOverride watchdog_usec{"WATCHDOG_USEC", std::nullopt};
    EnvOverride watchdog_pid{"WATCHDOG_PID", std::nullopt};
    Notifier notifier;
};

TEST_F(NotifierTest, SendsReadyStatusAndStopping) {
    EXPECT_TRUE(notifier.enabled());
    EXPECT_TRUE(notifier.ready());
    EXPECT_EQ(systemd.receive(kPatience), "READY=1");
    EXPECT_TRUE(notifier.status("device /dev/gimbal, link up"));
    EXPECT_EQ(systemd.receive(kPatience), "STATUS=device /dev/gimbal, link up");
    EXPECT_TRUE(notifier.stopping());
    EXPECT_EQ(systemd.receive(kPatience), "STOPPING=1");
}

TEST_F(NotifierTest, SendsReloadingWithItsMonotonicTime) {
    EXPECT_TRUE(notifier.reloading());
    const auto message = systemd.receive(kPatience);
    ASSERT_TRUE(message.has_value());
    EXPECT_TRUE(message->starts_with("RELOADING=1\nMONOTONIC_USEC=")) << *message;
    EXPECT_TRUE(notifier.ready());
    EXPECT_EQ(systemd.receive(kPatience), "READY=1");
}

TEST_F(NotifierTest, SendsStatusOnlyWhenItChanges) {
    EXPECT_TRUE(notifier.status("link up"));
    EXPECT_FALSE(notifier.status("link up"));
    EXPECT_TRUE(notifier.status("link stale"));
    EXPECT_EQ(systemd.receive(kPatience), "STATUS=link up");
    EXPECT_EQ(systemd.receive(kPatience), "STATUS=link stale");
    EXPECT_EQ(systemd.receive(100ms), std::nullopt);
}

TEST_F(NotifierTest, WatchdogPingsFromTheLoopAtHalfTheTimeout) {
    EnvOverride usec("WATCHDOG_USEC", "200000");
    EnvOverride pid("WATCHDOG_PID", std::to_string(getpid()));
    boost::asio::io_context io;
    WatchdogDriver driver(io, notifier);
    EXPECT_EQ(driver.start(), std::chrono::microseconds(100000));

    // Pings come only while the loop runs: three of them prove the timer
    // re-arms itself.
    int pings = 0;
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    while (pings < 3 && std::chrono::steady_clock::now() < deadline) {
        io.run_for(20ms);
        while (auto message = systemd.receive(0ms)) {
            EXPECT_EQ(*message, "WATCHDOG=1");
            ++pings;
        }
    }
    EXPECT_GE(pings, 3);

    driver.stop();
    io.restart();
    io.run_for(kPatience);  // returns at once: nothing is left to run
    EXPECT_TRUE(io.stopped());
}

TEST_F(NotifierTest, NoWatchdogWithoutWatchdogUsec) {
    boost::asio::io_context io;
    WatchdogDriver driver(io, notifier);
    EXPECT_EQ(driver.start(), std::nullopt);
    EXPECT_EQ(io.run(), 0U);
    EXPECT_EQ(systemd.receive(200ms), std::nullopt);
}

TEST_F(NotifierTest, NoWatchdogWhenMeantForAnotherProcess) {
    EnvOverride usec("WATCHDOG_USEC", "200000");
    EnvOverride pid("WATCHDOG_PID", std::to_string(getpid() + 1));
    boost::asio::io_context io;
    WatchdogDriver driver(io, notifier);
    EXPECT_EQ(driver.start(), std::nullopt);
    EXPECT_EQ(io.run(), 0U);
    EXPECT_EQ(systemd.receive(200ms), std::nullopt);
}

TEST(NotifierWithoutSystemd, EverythingIsANoOp) {
    EnvOverride notify_socket("NOTIFY_SOCKET", std::nullopt);
    Notifier notifier;
    EXPECT_FALSE(notifier.enabled());
    EXPECT_FALSE(notifier.ready());
    EXPECT_FALSE(notifier.status("link down"));
    EXPECT_FALSE(notifier.watchdog());
    EXPECT_FALSE(notifier.stopping());
}

TEST(NotifierWithoutSystemd, UnreachableSocketIsReportedNotFatal) {
    EnvOverride notify_socket("NOTIFY_SOCKET", "/nonexistent/gport/notify");
    Notifier notifier;
    EXPECT_TRUE(notifier.enabled());
    EXPECT_FALSE(notifier.ready());
    EXPECT_FALSE(notifier.watchdog());
}

}  // namespace
}  // namespace gport::systemd
