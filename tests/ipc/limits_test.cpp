// The server's limits over real sockets: re-entrancy, back-pressure, slots,
// idle timeout, fairness per turn, half-close and the peer's groups.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <grp.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <spdlog/sinks/ostream_sink.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <sstream>
#include <thread>

#include "emulation.hpp"
#include "server_harness.hpp"
#include "test_client.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::ServerHarness;
using testing::TestClient;
using namespace std::chrono_literals;

// Crash seen: Keepalive::end <- client_gone <- session_closed <- publish_event
// <- Keepalive::start. A session that overflows while an event is published
// reaches the core only after the publish returns.
TEST(Limits, OverflowDuringPublishReachesTheCoreAfterThePublish) {
    config::SocketConfig config;
    config.queue_limit = 8;
    ServerHarness h(config);
    TestClient stuck(h.path());
    ASSERT_EQ(stuck.call("subscribe", {{"topics", {"link"}}})["result"]["topics"].size(), 1u);
    h.on_io([&] {
        // Until the socket buffer and the 8-line queue are full: then it overflows.
        for (int i = 0; i < 1'000'000 && h.server->clients() == 1; ++i) {
            h.api.emit_link({daemon::LinkState::kStale, "no attitude for 500 ms"});
        }
    });
    EXPECT_TRUE(h.eventually([&] { return h.api.closed.size() == 1; }));
    EXPECT_EQ(h.on_io([&] { return h.api.reentered; }), 0);
    EXPECT_EQ(h.on_io([&] { return h.api.gone.size(); }), 1u) << "the deadman still runs";
}

// Back-pressure, not buffering: a client that sends batches and never reads
// has its requests wait instead of its replies piling up (or it being cut off).
TEST(Limits, AClientThatDoesNotReadIsNotReadEither) {
    config::SocketConfig config;
    config.max_requests_per_s = 100000;
    ServerHarness h(config);
    TestClient c(h.path());
    json batch = json::array();
    for (int i = 0; i < 32; ++i) {
        batch.push_back({{"id", i}, {"method", "status"}});
    }
    const std::string line = batch.dump() + "\n";
    constexpr int kBatches = 300;
    std::thread sender([&] {
        for (int i = 0; i < kBatches; ++i) {
            c.send(line);
        }
    });
    std::this_thread::sleep_for(500ms);
    // Bounded: the pause threshold plus one batch's replies.
    EXPECT_LT(h.on_io([&] { return h.server->queued_bytes(); }), 256u * 1024u);
    EXPECT_EQ(h.on_io([&] { return h.server->clients(); }), 1u) << "paused, not disconnected";
    int replies = 0;
    while (replies < kBatches) {
        auto reply = c.next();
        ASSERT_TRUE(reply.is_array()) << "after " << replies << " batches";
        ASSERT_EQ(reply.size(), 32u);
        ASSERT_TRUE(reply[31].contains("result")) << reply[31];
        ++replies;
    }
    sender.join();
}

TEST(Limits, ReadOnlyPeersCannotTakeTheReservedSlots) {
    config::SocketConfig config;
    config.max_clients = 4;
    config.reserved_command_slots = 2;
    ServerHarness h(config);
    h.on_io([&] { h.api.error = daemon::CommandError{daemon::ErrorCode::kPermission, "read"}; });
    TestClient a(h.path());
    TestClient b(h.path());
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 2; }));
    TestClient refused(h.path());
    auto reply = refused.next();
    EXPECT_EQ(reply["error"]["code"], -32004);
    EXPECT_THAT(reply["error"]["message"].get<std::string>(),
                HasSubstr("reserved for peers allowed to command (socket.reserved_command_slots)"));
    EXPECT_TRUE(refused.closed_by_server());
    h.on_io([&] { h.api.error.reset(); });  // now a peer that may command
    TestClient commander(h.path());
    EXPECT_EQ(commander.call("status")["result"]["clients"], 3);
}

TEST(Limits, OneUidCannotTakeEverySlot) {
    config::SocketConfig config;
    config.max_clients_per_uid = 2;
    ServerHarness h(config);
    TestClient a(h.path());
    TestClient b(h.path());
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 2; }));
    TestClient c(h.path());
    auto reply = c.next();
    EXPECT_EQ(reply["error"]["code"], -32004);
    EXPECT_THAT(reply["error"]["message"].get<std::string>(),
                HasSubstr("(2, socket.max_clients_per_uid)"));
}

// The rule: closed when it subscribes to nothing, holds no control, owns no
// motion, has no reply outstanding and sent nothing for idle_timeout_ms.
TEST(Limits, IdleConnectionsCloseButListenersAndControllersStay) {
    config::SocketConfig config;
    config.idle_timeout = 300ms;
    ServerHarness h(config);
    TestClient idle(h.path());
    TestClient listener(h.path());
    TestClient controller(h.path());
    listener.call("subscribe", {{"topics", {"link"}}});
    ASSERT_EQ(controller.call("acquire")["result"]["you_hold_control"], true);
    auto reply = idle.next();
    EXPECT_EQ(reply["error"]["code"], -32004);
    EXPECT_THAT(reply["error"]["message"].get<std::string>(),
                HasSubstr("idle for 300 ms with no subscription (socket.idle_timeout_ms)"));
    EXPECT_TRUE(idle.closed_by_server());
    std::this_thread::sleep_for(1s);  // several timeouts
    EXPECT_TRUE(listener.call("status")["result"].is_object());
    EXPECT_TRUE(controller.call("status")["result"].is_object());
}

// A flood is handled a few lines per loop turn: a handler posted while the
// first request runs gets its turn long before the last request.
TEST(Limits, AFloodIsHandledAFewLinesPerTurn) {
    config::SocketConfig config;
    config.max_requests_per_s = 100000;
    ServerHarness h(config);
    TestClient c(h.path());
    std::atomic<long> seen_at_marker{-1};
    h.on_io([&] {
        h.api.on_status = [&] {
            if (h.api.status_calls == 1) {
                boost::asio::post(h.io(),
                                  [&] { seen_at_marker = static_cast<long>(h.api.status_calls); });
            }
        };
    });
    std::string flood;
    for (int i = 0; i < 500; ++i) {
        flood += R"({"method":"status","id":1})"
                 "\n";
    }
    ASSERT_LT(flood.size(), 16384u);  // one read's worth
    c.send(flood);
    for (int i = 0; i < 500; ++i) {
        ASSERT_EQ(c.next()["id"], 1) << "reply " << i;
    }
    EXPECT_GE(seen_at_marker.load(), 1);
    EXPECT_LT(seen_at_marker.load(), 100);
}

// printf '{"id":1,"method":"get_settings"}\n' | socat - UNIX-CONNECT:... printed nothing.
TEST(Limits, HalfCloseRunsTheDeadmanAtOnceAndStillGetsEveryReply) {
    ServerHarness h;
    h.on_io([&] { h.api.defer = nullptr; });  // settings answer when the test says
    TestClient c(h.path());
    c.send(R"({"id":1,"method":"get_settings"})"
           "\n"
           R"([{"id":2,"method":"status"},{"id":3,"method":"get_settings"}])"
           "\n"
           R"({"id":4,"method":"stop"})");  // a last line without '\n'
    c.shutdown_write();
    ASSERT_TRUE(h.eventually([&] { return h.api.gone.size() == 1; }));
    EXPECT_TRUE(h.on_io([&] { return h.api.closed.empty(); }));
    ASSERT_TRUE(h.eventually([&] { return h.api.pending_settings.size() == 2; }));
    EXPECT_EQ(c.next()["id"], 4);
    h.on_io([&] { h.api.run_settings(); });
    EXPECT_EQ(c.next()["id"], 1);
    auto batch = c.next();
    ASSERT_TRUE(batch.is_array());
    EXPECT_EQ(batch.size(), 2u);
    EXPECT_TRUE(c.closed_by_server());
    EXPECT_TRUE(h.eventually([&] { return h.api.closed.size() == 1; }));
    EXPECT_EQ(h.on_io([&] { return h.api.gone.size(); }), 1u);
}

// Group membership is the peer process's own (SO_PEERGROUPS), not what the
// user database says about its uid.
TEST(Limits, PeerGroupsAreTheConnectingProcesssOwn) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "needs root to give a child process other groups";
    }
    if (auto missing = testing::so_peergroups_missing()) {
        GTEST_SKIP() << *missing;
    }
    ServerHarness h;
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, h.path().c_str(), sizeof(address.sun_path) - 1);
    const pid_t child = ::fork();
    if (child == 0) {
        // Plain system calls only: other threads may hold locks (malloc) at fork.
        const gid_t groups[] = {4242, 4343};
        const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
        if (::setgroups(2, groups) != 0 ||
            ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
            ::_exit(2);
        }
        const char request[] = "{\"id\":1,\"method\":\"stop\"}\n";
        char reply[512];
        const bool ok =
            ::write(fd, request, sizeof(request) - 1) > 0 && ::read(fd, reply, sizeof(reply)) > 0;
        ::_exit(ok ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ(WEXITSTATUS(status), 0);
    ASSERT_TRUE(h.eventually([&] { return h.api.gone.size() == 1; }));
    const auto groups = h.on_io([&] { return h.api.gone[0].groups; });
    EXPECT_THAT(groups, ::testing::UnorderedElementsAre(4242, 4343));
}

sockaddr_un address_of(const std::string& path) {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path.c_str(), sizeof(address.sun_path) - 1);
    return address;
}

// Accept failing with EMFILE busy-looped (100 % CPU, 1.2 M log lines): now it
// pauses, logs a summary, and serves the waiting clients once descriptors free up.
TEST(Limits, OutOfDescriptorsAcceptPausesLogsOnceAndResumes) {
    std::ostringstream out;
    auto log = std::make_shared<spdlog::logger>(
        "test", std::make_shared<spdlog::sinks::ostream_sink_mt>(out));
    ServerHarness h({}, log);
    std::vector<int> fds;
    for (int i = 0; i < 5; ++i) {
        fds.push_back(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    }
    rlimit saved{};
    ASSERT_EQ(::getrlimit(RLIMIT_NOFILE, &saved), 0);
    const int lowest_free = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
    ::close(lowest_free);
    rlimit low = saved;
    low.rlim_cur = static_cast<rlim_t>(lowest_free);  // no new descriptor fits
    ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &low), 0);
    const auto address = address_of(h.path());
    for (int fd : fds) {
        ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address));
    }
    std::this_thread::sleep_for(1s);
    ASSERT_EQ(::setrlimit(RLIMIT_NOFILE, &saved), 0);
    EXPECT_TRUE(h.eventually([&] { return h.server->clients() == fds.size(); }));
    const std::string request = "{\"id\":1,\"method\":\"stop\"}\n";
    for (int fd : fds) {
        ASSERT_EQ(::write(fd, request.data(), request.size()),
                  static_cast<ssize_t>(request.size()));
        pollfd p{fd, POLLIN, 0};
        EXPECT_EQ(::poll(&p, 1, 10000), 1) << "a reply comes";
        ::close(fd);
    }
    h.stop();
    const auto text = out.str();
    std::size_t failures = 0;
    for (auto at = text.find("accepting"); at != std::string::npos;
         at = text.find("accepting", at + 1)) {
        ++failures;
    }
    EXPECT_GE(failures, 1u) << text;
    EXPECT_LE(failures, 2u) << "a summary, not a flood";
    EXPECT_THAT(text, HasSubstr("pausing 250 ms"));
}

}  // namespace
}  // namespace gport::ipc
