// activated_socket_fd() with LISTEN_FDS/LISTEN_PID set up in-process, on
// real sockets put at fd 3 (and 4) for the duration of each test.
#include "gport/systemd/activation.hpp"

#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "test_fds.hpp"

namespace gport::systemd {
namespace {

using test::EnvOverride;
using test::FdOverride;
using ::testing::HasSubstr;

constexpr int kFirstFd = 3;  // SD_LISTEN_FDS_START

// A socket of the given type, listening on a temporary path when asked to.
class TestSocket {
  public:
    TestSocket(int type, bool listening) {
        fd = socket(AF_UNIX, type | SOCK_CLOEXEC, 0);
        if (!listening) {
            return;
        }
        char dir_template[] = "/tmp/gport-activation-XXXXXX";
        dir_ = mkdtemp(dir_template);
        path_ = dir_ + "/gportd.sock";
        sockaddr_un address{};
        address.sun_family = AF_UNIX;
        std::strncpy(address.sun_path, path_.c_str(), sizeof address.sun_path - 1);
        EXPECT_EQ(bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
        EXPECT_EQ(listen(fd, 4), 0);
    }
    ~TestSocket() {
        close(fd);
        if (!path_.empty()) {
            unlink(path_.c_str());
            rmdir(dir_.c_str());
        }
    }
    TestSocket(const TestSocket&) = delete;
    TestSocket& operator=(const TestSocket&) = delete;

    int fd = -1;

  private:
    std::string dir_;
    std::string path_;
};

class ActivationTest : public ::testing::Test {
  protected:
    const std::string pid = std::to_string(getpid());
    EnvOverride listen_fds{"LISTEN_FDS", std::nullopt};
    EnvOverride listen_pid{"LISTEN_PID", std::nullopt};
    EnvOverride listen_fdnames{"LISTEN_FDNAMES", std::nullopt};
};

TEST_F(ActivationTest, NoSocketWithoutListenFds) {
    EXPECT_EQ(activated_socket_fd(), std::nullopt);
}

TEST_F(ActivationTest, AcceptsOneListeningUnixStreamSocket) {
    TestSocket listener(SOCK_STREAM, true);
    FdOverride at_3(kFirstFd, listener.fd);
    setenv("LISTEN_FDS", "1", 1);
    setenv("LISTEN_PID", pid.c_str(), 1);

    EXPECT_EQ(activated_socket_fd(), kFirstFd);
    // Not inherited by anything the daemon starts.
    EXPECT_EQ(std::getenv("LISTEN_FDS"), nullptr);
    EXPECT_EQ(std::getenv("LISTEN_PID"), nullptr);
    EXPECT_NE(fcntl(kFirstFd, F_GETFD) & FD_CLOEXEC, 0);
}

TEST_F(ActivationTest, IgnoresSocketsMeantForAnotherProcess) {
    TestSocket listener(SOCK_STREAM, true);
    FdOverride at_3(kFirstFd, listener.fd);
    setenv("LISTEN_FDS", "1", 1);
    setenv("LISTEN_PID", std::to_string(getpid() + 1).c_str(), 1);
    EXPECT_EQ(activated_socket_fd(), std::nullopt);
}

TEST_F(ActivationTest, RefusesMoreThanOneSocket) {
    TestSocket first(SOCK_STREAM, true);
    TestSocket second(SOCK_STREAM, true);
    FdOverride at_3(kFirstFd, first.fd);
    FdOverride at_4(kFirstFd + 1, second.fd);
    setenv("LISTEN_FDS", "2", 1);
    setenv("LISTEN_PID", pid.c_str(), 1);
    try {
        activated_socket_fd();
        FAIL() << "two sockets were accepted";
    } catch (const ActivationError& error) {
        EXPECT_THAT(error.what(), HasSubstr("passed 2 sockets"));
        EXPECT_THAT(error.what(), HasSubstr("exactly one listening AF_UNIX stream socket"));
    }
}

TEST_F(ActivationTest, RefusesASocketThatDoesNotListen) {
    int pair[2];
    ASSERT_EQ(socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, pair), 0);
    {
        FdOverride at_3(kFirstFd, pair[0]);
        setenv("LISTEN_FDS", "1", 1);
        setenv("LISTEN_PID", pid.c_str(), 1);
        EXPECT_THROW(
            {
                try {
                    activated_socket_fd();
                } catch (const ActivationError& error) {
                    EXPECT_THAT(error.what(),
                                HasSubstr("is not a listening AF_UNIX stream socket"));
                    throw;
                }
            },
            ActivationError);
    }
    close(pair[0]);
    close(pair[1]);
}

TEST_F(ActivationTest, RefusesADatagramSocket) {
    TestSocket datagram(SOCK_DGRAM, false);
    FdOverride at_3(kFirstFd, datagram.fd);
    setenv("LISTEN_FDS", "1", 1);
    setenv("LISTEN_PID", pid.c_str(), 1);
    EXPECT_THROW(activated_socket_fd(), ActivationError);
}

TEST_F(ActivationTest, RefusesMalformedVariables) {
    setenv("LISTEN_FDS", "one", 1);
    setenv("LISTEN_PID", pid.c_str(), 1);
    EXPECT_THROW(activated_socket_fd(), ActivationError);
}

}  // namespace
}  // namespace gport::systemd
