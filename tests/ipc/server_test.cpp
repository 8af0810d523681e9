// The socket server over a real Unix socket: framing, limits, sessions and
// the socket file's life cycle.
#include <gmock/gmock.h>
#include <grp.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "server_harness.hpp"
#include "test_client.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::ServerHarness;
using testing::TestClient;

TEST(Server, AnswersRequestsAndCountsClients) {
    ServerHarness h;
    TestClient a(h.path());
    TestClient b(h.path());
    ASSERT_TRUE(a.connected() && b.connected());
    EXPECT_EQ(b.call("stop")["result"]["sent"], true);
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 2; }));
    auto status = a.call("status")["result"];
    EXPECT_EQ(status["clients"], 2);
    EXPECT_GT(status["client"]["id"].get<int>(), 0);
    EXPECT_EQ(status["client"]["pid"], static_cast<int>(::getpid()));
    EXPECT_EQ(status["client"]["uid"], static_cast<int>(::getuid()));
    // Settings answer later, from the loop.
    EXPECT_EQ(a.call("set_settings", {{"dead_zone", 3}})["result"]["dead_zone"], 3);
    EXPECT_EQ(a.call("get_settings")["result"]["dead_zone"], 3);
}

TEST(Server, MalformedJsonAndGarbageKeepTheConnection) {
    ServerHarness h;
    TestClient c(h.path());
    c.send("{\"id\":1,\"method\":\n");
    EXPECT_EQ(c.next()["error"]["code"], -32700);
    std::string garbage;
    for (int i = 0; i < 4096; ++i) {
        garbage += static_cast<char>((i * 7919) % 256);
    }
    c.send(garbage + "\n");  // several lines of garbage: parse errors, skipped by call()
    EXPECT_EQ(c.call("center")["result"]["sent"], true);
    c.send("\r\n   \n{\"id\":9,\"method\":\"lock\"}\r\n");
    EXPECT_EQ(c.next()["id"], 9);
}

TEST(Server, OverlongLineGetsAnErrorThenTheConnectionCloses) {
    config::SocketConfig config;
    config.line_limit = 1024;
    ServerHarness h(config);
    TestClient c(h.path());
    c.send(std::string(1000, ' '));
    c.send(std::string(1000, 'x'));
    auto reply = c.next();
    EXPECT_EQ(reply["error"]["code"], -32600);
    EXPECT_THAT(reply["error"]["message"].get<std::string>(), HasSubstr("longer than 1024 bytes"));
    EXPECT_TRUE(c.closed_by_server());
    EXPECT_TRUE(h.eventually([&] { return h.api.gone.size() == 1; }));
    // A line of exactly the limit is fine.
    TestClient d(h.path());
    std::string padded = R"({"id":1,"method":"stop"})";
    padded.resize(1024, ' ');
    d.send(padded + "\n");
    EXPECT_EQ(d.next()["result"]["sent"], true);
}

TEST(Server, TheClientTooManyHearsWhyAndIsClosed) {
    config::SocketConfig config;
    config.max_clients = 2;
    ServerHarness h(config);
    auto a = std::make_unique<TestClient>(h.path());
    TestClient b(h.path());
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 2; }));
    TestClient c(h.path());
    auto refused = c.next();
    EXPECT_EQ(refused["error"]["code"], -32004);
    EXPECT_EQ(refused["error"]["message"], "too many clients (2)");
    EXPECT_TRUE(c.closed_by_server());
    a.reset();
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 1; }));
    TestClient d(h.path());
    EXPECT_EQ(d.call("status")["result"]["clients"], 2);
}

TEST(Server, ClientGoneIsCalledOnDisconnectWithItsIdentity) {
    ServerHarness h;
    {
        TestClient c(h.path());
        ASSERT_EQ(c.call("photo")["result"]["sent"], true);
    }
    ASSERT_TRUE(h.eventually([&] { return h.api.gone.size() == 1; }));
    auto gone = h.on_io([&] { return h.api.gone[0]; });
    EXPECT_EQ(gone.pid, ::getpid());
    EXPECT_EQ(gone.uid, ::getuid());
    EXPECT_EQ(h.on_io([&] { return h.api.calls[0]; }), fmt::format("photo by {}", gone.id));
}

TEST(Server, ReplacesAStaleSocketFile) {
    const auto dir = testing::make_temp_dir();
    const auto path = dir + "/gportd.sock";
    {
        // A socket file nobody listens on, as a crashed daemon leaves it.
        boost::asio::io_context io;
        boost::asio::local::stream_protocol::acceptor stale(
            io, boost::asio::local::stream_protocol::endpoint(path));
    }
    ASSERT_TRUE(std::filesystem::exists(path));
    boost::asio::io_context io;
    testing::FakeApi api;
    config::SocketConfig config;
    config.path = path;
    config.mode = 0600;
    Server server(io, api, config, testing::quiet_logger());
    EXPECT_NO_THROW(server.start());
    EXPECT_EQ(api.observer, &server);
    struct stat info {};
    ASSERT_EQ(::stat(path.c_str(), &info), 0);
    EXPECT_EQ(info.st_mode & 07777, 0600u);
    server.close();
    EXPECT_EQ(api.observer, nullptr);
    EXPECT_FALSE(std::filesystem::exists(path)) << "the server removes the file it made";
    std::filesystem::remove_all(dir);
}

TEST(Server, RefusesToStartWhereAnotherDaemonListens) {
    ServerHarness running;
    boost::asio::io_context io;
    testing::FakeApi api;
    config::SocketConfig config;
    config.path = running.path();
    Server second(io, api, config, testing::quiet_logger());
    try {
        second.start();
        FAIL() << "started over a live socket";
    } catch (const std::runtime_error& e) {
        EXPECT_THAT(e.what(), HasSubstr("another daemon is already listening"));
        EXPECT_THAT(e.what(), HasSubstr(running.path()));
    }
    TestClient c(running.path());
    EXPECT_EQ(c.call("stop")["result"]["sent"], true) << "the first daemon is untouched";
}

TEST(Server, RefusesToReplaceSomethingThatIsNotASocket) {
    const auto dir = testing::make_temp_dir();
    config::SocketConfig config;
    config.path = dir + "/gportd.sock";
    std::ofstream(config.path) << "precious";
    boost::asio::io_context io;
    testing::FakeApi api;
    Server server(io, api, config, testing::quiet_logger());
    EXPECT_THROW(server.start(), std::runtime_error);
    std::ifstream in(config.path);
    std::string content;
    in >> content;
    EXPECT_EQ(content, "precious");
    std::filesystem::remove_all(dir);
}

TEST(Server, AppliesGroupByNameAndRefusesAnUnknownGroup) {
    const auto dir = testing::make_temp_dir();
    config::SocketConfig config;
    config.path = dir + "/gportd.sock";
    const group* own = ::getgrgid(::getgid());
    ASSERT_NE(own, nullptr);
    config.group = own->gr_name;
    boost::asio::io_context io;
    testing::FakeApi api;
    {
        Server server(io, api, config, testing::quiet_logger());
        ASSERT_NO_THROW(server.start());
        struct stat info {};
        ASSERT_EQ(::stat(config.path.c_str(), &info), 0);
        EXPECT_EQ(info.st_gid, ::getgid());
        EXPECT_EQ(info.st_mode & 07777, 0660u);
    }
    config.group = "no-such-group-gport";
    Server server(io, api, config, testing::quiet_logger());
    try {
        server.start();
        FAIL() << "started with an unknown group";
    } catch (const std::runtime_error& e) {
        EXPECT_THAT(e.what(), HasSubstr("\"no-such-group-gport\" does not exist"));
    }
    std::filesystem::remove_all(dir);
}

TEST(Server, UsesAnAlreadyListeningSocket) {
    const auto dir = testing::make_temp_dir();
    const auto path = dir + "/activated.sock";
    boost::asio::io_context io;
    boost::asio::local::stream_protocol::acceptor listening(
        io, boost::asio::local::stream_protocol::endpoint(path));
    testing::FakeApi api;
    config::SocketConfig config;
    config.path = dir + "/not-used.sock";
    Server server(io, api, config, testing::quiet_logger(), listening.release());
    server.start();
    EXPECT_FALSE(std::filesystem::exists(config.path));
    std::thread runner([&] { io.run(); });
    {
        TestClient c(path);
        EXPECT_EQ(c.call("center")["result"]["sent"], true);
    }
    boost::asio::post(io, [&] { server.close(); });
    runner.join();  // close() lets run() return
    EXPECT_TRUE(std::filesystem::exists(path)) << "the socket unit owns that file";
    std::filesystem::remove_all(dir);
}

TEST(Server, CloseEndsSessionsAndLetsRunReturn) {
    ServerHarness h;
    TestClient a(h.path());
    TestClient b(h.path());
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 2; }));
    h.stop();
    EXPECT_TRUE(a.closed_by_server());
    EXPECT_TRUE(b.closed_by_server());
    EXPECT_EQ(h.api.gone.size(), 2u);
    EXPECT_FALSE(std::filesystem::exists(h.path()));
}

}  // namespace
}  // namespace gport::ipc
