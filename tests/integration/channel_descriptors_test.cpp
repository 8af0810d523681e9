// When the kernel refuses to pass the attitude channel's descriptors:
// gportd runs as uid 65533 (a uid of its own: descriptors in flight are
// counted per user, and other tests run gportd as 65534) without
// capabilities and with a small RLIMIT_NOFILE, and another process of the
// same uid holds more descriptors in flight than that limit (as in issue
// 22's problem 3), so gportd's sendmsg fails with ETOOMANYREFS. The reply
// that announced them becomes -32603, the failure is counted, and the next
// request, once the shortage is over, sends them (docs/api.md, "Errors and
// exhaustion").
#include <fcntl.h>
#include <grp.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <string>
#include <vector>

#include "channel_client.hpp"
#include "gport/base/descriptors.hpp"
#include "harness.hpp"

namespace gport::testing {
namespace {

constexpr uid_t kUid = 65533;        // gportd's and the hoarder's
constexpr int kInFlight = 400;       // descriptors the hoarder holds in flight
constexpr int kDaemonFiles = 64;     // gportd's RLIMIT_NOFILE, far below
constexpr int kPerMessage = 200;     // under SCM_MAX_FD (253)
constexpr unsigned kLifetime = 100;  // seconds, the hoarder's at most (SIGALRM)

// A process of gportd's uid that puts kInFlight descriptors in flight on a
// socket pair nobody reads, says so on `ready`, and lets them go (exits)
// when `go` is written or closed (`others`: the parent's ends of the two
// pipes, closed here, or `go` would never see its end). It never outlives
// kLifetime, whatever the test does. Only async-signal-safe calls after fork.
[[noreturn]] void hoard_in_flight(int ready, int go, std::array<int, 2> others) {
    ::close(others[0]);
    ::close(others[1]);
    ::alarm(kLifetime);
    const rlimit files{4096, 4096};
    int pair[2];
    if (::setgroups(0, nullptr) != 0 || ::setrlimit(RLIMIT_NOFILE, &files) != 0 ||
        ::setgid(kUid) != 0 || ::setuid(kUid) != 0 ||
        ::socketpair(AF_UNIX, SOCK_STREAM, 0, pair) != 0) {
        ::_exit(1);
    }
    const int null = ::open("/dev/null", O_RDONLY);
    int fds[kPerMessage];
    for (int& fd : fds) {
        fd = null;
    }
    for (int sent = 0; sent < kInFlight; sent += kPerMessage) {
        const char byte = 'x';
        if (base::send_with_descriptors(pair[0], &byte, 1, fds, 0) != 1) {
            ::_exit(2);
        }
    }
    char byte = 'r';
    if (::write(ready, &byte, 1) != 1) {
        ::_exit(3);
    }
    [[maybe_unused]] const auto n = ::read(go, &byte, 1);
    ::_exit(0);  // the unread messages go, and their descriptors with them
}

class Hoarder {
  public:
    Hoarder() {
        int ready[2];
        int go[2];
        if (::pipe2(ready, O_CLOEXEC) != 0 || ::pipe2(go, O_CLOEXEC) != 0) {
            return;
        }
        pid_ = ::fork();
        if (pid_ == 0) {
            hoard_in_flight(ready[1], go[0], {ready[0], go[1]});
        }
        ::close(ready[1]);
        ::close(go[0]);
        go_ = go[1];
        char byte = 0;
        ready_ = pid_ > 0 && ::read(ready[0], &byte, 1) == 1;
        ::close(ready[0]);
    }
    ~Hoarder() { release(); }
    bool ready() const { return ready_; }
    // Lets the descriptors go and waits until they are gone.
    void release() {
        if (go_ >= 0) {
            ::close(go_);
            go_ = -1;
        }
        if (pid_ > 0) {
            int status = 0;
            ::waitpid(pid_, &status, 0);
            pid_ = -1;
        }
    }

  private:
    pid_t pid_ = -1;
    int go_ = -1;
    bool ready_ = false;
};

std::string unprivileged_skip() {
    if (::getuid() != 0) {
        return "needs root, to run gportd and the hoarder as another uid (root passes any "
               "number of descriptors)";
    }
    for (const char* tool : {"/usr/bin/setpriv", "/usr/bin/prlimit"}) {
        if (::access(tool, X_OK) != 0) {
            return std::string("needs ") + tool + " (util-linux)";
        }
    }
    return "";
}

TEST(ChannelDescriptors, RefusedBySendmsgTheyAreCountedAndSentWithTheNextRequest) {
    if (const auto why = unprivileged_skip(); !why.empty()) {
        GTEST_SKIP() << why;
    }
    TempDir dir;
    ASSERT_EQ(::chmod(dir.path().c_str(), 0777), 0);  // gportd (kUid) makes its socket there
    const std::string files = "--nofile=" + std::to_string(kDaemonFiles);
    DaemonProcess daemon(dir, {"--simulate"}, {}, R"("socket": {"max_clients": 16})",
                         {"/usr/bin/prlimit", files, "--", "/usr/bin/setpriv",
                          "--reuid=" + std::to_string(kUid), "--regid=" + std::to_string(kUid),
                          "--clear-groups", "--inh-caps=-all", "--bounding-set=-all", "--"});
    ASSERT_TRUE(eventually([&] { return ::access(daemon.socket().c_str(), F_OK) == 0; }));
    DescriptorClient reader(daemon.socket());
    ASSERT_TRUE(reader.connected());
    ASSERT_TRUE(reader.call("status").contains("result"));
    Hoarder hoarder;
    ASSERT_TRUE(hoarder.ready()) << "the hoarder could not put descriptors in flight";
    const auto refused = reader.call("attitude_channel");
    ASSERT_TRUE(refused.contains("error")) << refused;
    EXPECT_EQ(refused["error"]["code"], -32603);
    EXPECT_EQ(refused["error"]["message"],
              "attitude channel unavailable: sending its descriptors: Too many references: "
              "cannot splice")
        << refused;
    EXPECT_EQ(reader.descriptors(), 0u);
    EXPECT_EQ(reader.call("status")["result"]["attitude_channel_failures"], 1);
    hoarder.release();
    const auto sent = reader.call("attitude_channel");
    ASSERT_TRUE(sent.contains("result")) << sent;
    EXPECT_EQ(sent["result"]["descriptors"], 2);
    ASSERT_EQ(reader.descriptors(), 2u);
    const int ring = reader.take_descriptor();
    const int wake = reader.take_descriptor();
    RingMapping ring_mapping(ring, base::ring_bytes(64));
    WakeMapping wake_mapping(wake);
    ::close(ring);
    ::close(wake);
    EXPECT_EQ(ring_mapping.check(), std::nullopt);
    EXPECT_EQ(wake_mapping.check(), std::nullopt);
    // Later requests: none again, and no further failure.
    EXPECT_EQ(reader.call("attitude_channel")["result"]["descriptors"], 0);
    EXPECT_EQ(reader.call("status")["result"]["attitude_channel_failures"], 1);
}

}  // namespace
}  // namespace gport::testing
