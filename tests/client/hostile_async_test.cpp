// AsyncClient against a hostile gportd (issue 22 item 7): the same line and
// nesting limits as the blocking client, and a timeout for its calls.
#include <gtest/gtest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <string>

#include "gport/client/async_client.hpp"
#include "hostile_server.hpp"

namespace gport::testing {
namespace {

namespace gc = gport::client;
namespace asio = boost::asio;
using nlohmann::json;
using namespace std::chrono_literals;

constexpr std::uint64_t kMiB = 1024 * 1024;

class HostileAsync : public ::testing::Test {
  protected:
    // Runs the loop until `done` or 60 s (a failure, not a measurement).
    bool run_until(const bool& done) {
        asio::steady_timer guard(io_, 60s);
        guard.async_wait([&](boost::system::error_code ec) {
            if (!ec) {
                io_.stop();
            }
        });
        while (!done && !io_.stopped()) {
            io_.run_one();
        }
        guard.cancel();
        io_.restart();
        io_.poll();
        io_.restart();
        return done;
    }

    void connect(gc::AsyncClient& client, const std::string& path) {
        bool done = false;
        client.async_connect(path, [&](std::optional<gc::Error> error) {
            EXPECT_FALSE(error) << error->what();
            done = true;
        });
        ASSERT_TRUE(run_until(done));
    }

    // The error async_status completes with (none: a failure).
    gc::Error status_error(gc::AsyncClient& client) {
        std::optional<gc::Error> result;
        bool done = false;
        client.async_status([&](std::optional<gc::Error> error, gc::Status) {
            result = error;
            done = true;
        });
        EXPECT_TRUE(run_until(done)) << "the call never completed";
        EXPECT_TRUE(result.has_value()) << "no error";
        return result.value_or(gc::Error(0, "none"));
    }

    asio::io_context io_;
};

TEST_F(HostileAsync, LineWithoutEndStopsAtTheLineLimit) {
    HostileServer server([](HostilePeer& peer, const json&) { peer.stream(400 * kMiB); });
    gc::AsyncClient client(io_);
    std::optional<gc::Error> disconnected;
    client.on_disconnect([&](const gc::Error& e) { disconnected = e; });
    connect(client, server.path());
    const auto before = reset_peak_rss();
    const auto e = status_error(client);
    const auto growth = peak_rss_growth_kib(before);
    std::printf("async, 400 MB line: peak RSS grew %llu KiB; the server sent %llu bytes\n",
                static_cast<unsigned long long>(growth),
                static_cast<unsigned long long>(server.bytes_sent()));
    EXPECT_TRUE(e.transport()) << e.what();
    EXPECT_NE(e.message().find("16777216"), std::string::npos) << e.message();
    ASSERT_TRUE(disconnected.has_value()) << "on_disconnect was called";
    EXPECT_EQ(disconnected->message(), e.message());
    EXPECT_FALSE(client.connected());
    EXPECT_LT(server.bytes_sent(), 64 * kMiB) << "the client stopped reading at the limit";
    if (kRssMeasured) {
        EXPECT_LT(growth, 64 * 1024) << "KiB of peak RSS growth";
    }
}

TEST_F(HostileAsync, JsonNestedAMillionDeepEndsTheConnection) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        peer.send(R"({"jsonrpc":"2.0","id":)" + request.at("id").dump() + R"(,"result":)" +
                  std::string(1'000'000, '[') + std::string(1'000'000, ']') + "}\n");
    });
    gc::AsyncClient client(io_);
    connect(client, server.path());
    const auto e = status_error(client);
    EXPECT_TRUE(e.transport()) << e.what();
    EXPECT_NE(e.message().find("nested deeper than 64"), std::string::npos) << e.message();
    EXPECT_FALSE(client.connected());
}

TEST_F(HostileAsync, ALineThatIsNotJsonEndsTheConnection) {
    HostileServer server([](HostilePeer& peer, const json&) { peer.send("{\"id\":1,]\n"); });
    gc::AsyncClient client(io_);
    connect(client, server.path());
    const auto e = status_error(client);
    EXPECT_TRUE(e.transport()) << e.what();
    EXPECT_NE(e.message().find("not JSON"), std::string::npos) << e.message();
}

TEST_F(HostileAsync, ASilentServerGivesATimeoutAndTheConnectionStays) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        if (request.at("method") == "photo") {
            peer.reply(request, {{"sent", true}});
        }
    });
    gc::AsyncClient client(io_);
    EXPECT_EQ(client.call_timeout(), gc::kDefaultCallTimeout);
    client.set_call_timeout(200ms);
    connect(client, server.path());
    const auto e = status_error(client);
    EXPECT_TRUE(e.is(gc::ErrorCode::kTimeout)) << e.what();
    EXPECT_NE(e.message().find("no reply to status within 200 ms"), std::string::npos)
        << e.message();
    EXPECT_TRUE(client.connected());
    bool done = false;
    client.async_photo([&](std::optional<gc::Error> error, gc::Done) {
        EXPECT_FALSE(error) << error->what();
        done = true;
    });
    EXPECT_TRUE(run_until(done));
}

TEST_F(HostileAsync, AServerThatNeverReadsEndsTheConnection) {
    HostileServer server(nullptr);
    gc::AsyncClient client(io_);
    client.set_call_timeout(300ms);
    connect(client, server.path());
    // 100,000 topics of 100 bytes: a request line of ~10 MB that the socket
    // buffers cannot hold.
    const std::vector<std::string> topics(100'000, std::string(100, 't'));
    std::optional<gc::Error> result;
    bool done = false;
    client.async_subscribe(topics, std::nullopt,
                           [&](std::optional<gc::Error> error, gc::Subscription) {
                               result = error;
                               done = true;
                           });
    ASSERT_TRUE(run_until(done));
    ASSERT_TRUE(result.has_value());
    EXPECT_TRUE(result->transport()) << result->what();
    EXPECT_NE(result->message().find("did not read the request to subscribe"), std::string::npos)
        << result->message();
    EXPECT_FALSE(client.connected());
}

TEST_F(HostileAsync, WithoutACallTimeoutACallWaits) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        std::this_thread::sleep_for(300ms);
        peer.reply(request, {{"sent", true}});
    });
    gc::AsyncClient client(io_);
    client.set_call_timeout(std::nullopt);
    connect(client, server.path());
    bool done = false;
    client.async_photo([&](std::optional<gc::Error> error, gc::Done) {
        EXPECT_FALSE(error) << error->what();
        done = true;
    });
    EXPECT_TRUE(run_until(done));
}

}  // namespace
}  // namespace gport::testing
