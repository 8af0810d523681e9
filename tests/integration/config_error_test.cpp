// gportd started by socket activation with a configuration it cannot load
// (docs/operations.md, "A bad configuration under systemd"): it stays up on
// the socket it was given and answers every request with -32006 naming the
// key, whatever the clients do, until SIGTERM (exit 0) or a SIGHUP that
// finds the file fixed (exit 75, for systemd to start it again).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "process.hpp"
#include "unix_connect.hpp"

namespace gport::testing {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

constexpr const char* kBadConfig = R"({"keepalive": {"rate_hz": 1000}})";

// A listening socket at `path`, as systemd makes for gportd.socket.
int listen_at(const std::string& path) {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    path.copy(addr.sun_path, sizeof(addr.sun_path) - 1);
    if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
        ::listen(fd, 64) != 0) {
        return -1;
    }
    return fd;
}

// gportd with `listener` passed as systemd does: fd 3, LISTEN_FDS=1,
// LISTEN_PID its own pid. stderr (its journal lines) to `log`.
pid_t start_activated(int listener, const std::string& config, const std::string& log) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (listener == 3) {
            ::fcntl(3, F_SETFD, 0);  // dup2 onto itself would keep FD_CLOEXEC
        } else {
            ::dup2(listener, 3);  // dup2 clears FD_CLOEXEC on the copy
        }
        const std::string pid_text = std::to_string(::getpid());
        ::setenv("LISTEN_FDS", "1", 1);
        ::setenv("LISTEN_PID", pid_text.c_str(), 1);
        ::unsetenv("NOTIFY_SOCKET");
        ::unsetenv("WATCHDOG_USEC");
        std::FILE* out = std::freopen(log.c_str(), "w", stderr);
        (void)out;
        ::execl(GPORTD_PATH, GPORTD_PATH, "--config", config.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    return pid;
}

// One request on a new connection: the reply line ("" if none).
std::string ask(const std::string& socket, const std::string& request) {
    const int fd = connect_unix(socket);
    if (fd < 0) {
        return "";
    }
    const timeval timeout{10, 0};  // a daemon that is gone fails the test, never hangs it
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
    // MSG_NOSIGNAL: a connection the daemon closed (over its limit) is an
    // empty answer, not a SIGPIPE.
    (void)!::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
    std::string reply;
    char buffer[4096];
    ssize_t n = 0;
    while (reply.find('\n') == std::string::npos && (n = ::read(fd, buffer, sizeof(buffer))) > 0) {
        reply.append(buffer, static_cast<std::size_t>(n));
    }
    ::close(fd);
    return reply;
}

bool running(pid_t pid) {
    int status = 0;
    return ::waitpid(pid, &status, WNOHANG) == 0;
}

int exit_status(pid_t pid) {
    int status = 0;
    for (int i = 0; i < 1000; ++i) {
        if (::waitpid(pid, &status, WNOHANG) == pid) {
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        std::this_thread::sleep_for(10ms);
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    return -1;
}

struct Activated : ::testing::Test {
    void SetUp() override {
        config = dir.file("gportd.json");
        socket = dir.file("gportd.sock");
        std::ofstream(config) << kBadConfig;
        listener = listen_at(socket);
        ASSERT_GE(listener, 0);
        pid = start_activated(listener, config, dir.file("stderr"));
        ASSERT_GT(pid, 0);
        // Serving (its signal handlers in place) once a request is answered.
        ASSERT_TRUE(eventually(
            [&] {
                return ask(socket, R"({"id":0,"method":"status"})"
                                   "\n")
                           .find("-32006") != std::string::npos;
            },
            10s))
            << log();
    }
    void TearDown() override {
        if (pid > 0 && running(pid)) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, nullptr, 0);
        }
        ::close(listener);
    }
    std::string log() const {
        std::ifstream in(dir.file("stderr"));
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }

    TempDir dir;
    std::string config;
    std::string socket;
    int listener = -1;
    pid_t pid = -1;
};

TEST_F(Activated, EveryRequestGetsTheConfigErrorAndTheDaemonStays) {
    for (int i = 1; i <= 30; ++i) {  // a client retrying in a loop
        const auto reply = json::parse(ask(socket, R"({"jsonrpc":"2.0","id":)" + std::to_string(i) +
                                                       R"(,"method":"status"})"
                                                       "\n"),
                                       nullptr, false);
        ASSERT_TRUE(reply.is_object()) << "request " << i;
        EXPECT_EQ(reply["id"], i);
        EXPECT_EQ(reply["error"]["code"], -32006);
        const std::string message = reply["error"]["message"];
        EXPECT_NE(message.find("keepalive.rate_hz"), std::string::npos) << message;
        EXPECT_NE(message.find("systemctl restart gportd"), std::string::npos) << message;
    }
    EXPECT_TRUE(running(pid)) << log();
    // Not a request, an over-long line, a string id: each answered, id kept or null.
    EXPECT_NE(ask(socket, "hello\n").find(R"("id":null)"), std::string::npos);
    EXPECT_NE(ask(socket, std::string(70 * 1024, '[') + "\n").find("-32006"), std::string::npos);
    EXPECT_NE(ask(socket, R"({"id":"x","method":"stop"})"
                          "\n")
                  .find(R"("id":"x")"),
              std::string::npos);
    // Logged once, however many clients came.
    const auto text = log();
    std::size_t lines = 0;
    for (auto at = text.find("configuration error"); at != std::string::npos;
         at = text.find("configuration error", at + 1)) {
        ++lines;
    }
    EXPECT_EQ(lines, 1u) << text;
    ::kill(pid, SIGTERM);
    EXPECT_EQ(exit_status(pid), 0);
}

TEST_F(Activated, SilentAndVanishingClientsAreLetGoAndOthersStillServed) {
    std::vector<int> silent;
    for (int i = 0; i < 40; ++i) {  // more than the 16 it serves at once
        silent.push_back(connect_unix(socket));
    }
    const int gone = connect_unix(socket);
    ::close(gone);
    // The silent ones are closed after the read timeout; then a client is answered.
    EXPECT_TRUE(eventually(
        [&] {
            return ask(socket, R"({"id":1,"method":"status"})"
                               "\n")
                       .find("-32006") != std::string::npos;
        },
        10s));
    for (const int fd : silent) {
        ::close(fd);
    }
    EXPECT_TRUE(running(pid)) << log();
}

TEST_F(Activated, AReloadWithTheFileStillBadKeepsServingAFixedOneExits75) {
    std::ofstream(config) << R"({"keepalive": {"rate_hz": 2000}})";
    ::kill(pid, SIGHUP);
    EXPECT_TRUE(eventually([&] { return log().find("2000") != std::string::npos; }, 5s)) << log();
    EXPECT_TRUE(running(pid));
    EXPECT_NE(ask(socket, R"({"id":2,"method":"status"})"
                          "\n")
                  .find("-32006"),
              std::string::npos);
    std::ofstream(config) << "{}";
    ::kill(pid, SIGHUP);
    EXPECT_EQ(exit_status(pid), 75) << log();
    EXPECT_NE(log().find("the configuration loads now"), std::string::npos) << log();
}

}  // namespace
}  // namespace gport::testing
