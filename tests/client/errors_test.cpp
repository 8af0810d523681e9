// Errors of the blocking Client: the daemon's refusals as Error with the API
// code, and transport errors when gportd is absent or goes away.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "client_fixture.hpp"

namespace gport::testing {
namespace {

using ClientErrors = SimulatedDaemonTest;

TEST_F(ClientErrors, InvalidParamsCarryCodeAndMessage) {
    try {
        client().angle({.pitch = 400});
        FAIL() << "no error";
    } catch (const gc::Error& e) {
        EXPECT_EQ(e.code(), -32602);
        EXPECT_TRUE(e.is(gc::ErrorCode::kInvalidParams));
        EXPECT_FALSE(e.transport());
        EXPECT_NE(e.message().find("pitch"), std::string::npos) << e.message();
        EXPECT_NE(std::string(e.what()).find("-32602"), std::string::npos) << e.what();
    }
    EXPECT_EQ(client().status().link.state, "up") << "the connection stays usable";
}

TEST_F(ClientErrors, AnotherClientHoldsControl) {
    auto other = gc::Client::connect(socket());
    other.acquire();
    try {
        client().speed({.yaw = 10}, 1000ms);
        FAIL() << "no error";
    } catch (const gc::Error& e) {
        EXPECT_TRUE(e.is(gc::ErrorCode::kBusy)) << e.what();
        EXPECT_NE(e.message().find(std::to_string(::getpid())), std::string::npos)
            << "names the holder's pid: " << e.message();
    }
    EXPECT_NO_THROW(client().stop()) << "stop is never restricted by acquire";
    other.release();
    EXPECT_NO_THROW(client().center());
}

TEST_F(ClientErrors, ReadOnlyPeerMayReadButNotCommand) {
    if (::geteuid() != 0) {
        GTEST_SKIP() << "needs root to run a client as another user";
    }
    daemon_.reset();
    client_.reset();
    ::chmod(dir_.path().c_str(), 0755);  // nobody must reach the socket
    start(R"("socket": {"mode": "0666"}, "access": {"control_uids": [4242]})");
    // nobody may not read the build tree (under /root on a CI machine): the
    // probe runs from a copy, with the library beside it.
    const auto probe_dir = dir_.file("probe");
    std::filesystem::create_directory(probe_dir);
    std::filesystem::copy_file(CLIENT_PROBE_PATH, probe_dir + "/client_probe");
    std::filesystem::copy_file(
        CLIENT_LIBRARY_PATH,
        probe_dir + "/" + std::filesystem::path(CLIENT_LIBRARY_PATH).filename().string());
    ::chmod(probe_dir.c_str(), 0755);
    const auto as_nobody = [&](const std::string& method) {
        Process probe({"/usr/bin/env", "LD_LIBRARY_PATH=" + probe_dir, "/usr/bin/setpriv",
                       "--reuid=65534", "--regid=65534", "--clear-groups",
                       probe_dir + "/client_probe", socket(), method});
        auto line = probe.next_line();
        probe.wait();
        return line.value_or("(nothing)");
    };
    EXPECT_EQ(as_nobody("status"), "ok");
    EXPECT_EQ(as_nobody("center"), "-32001");
}

TEST(ClientLinkDown, CommandsFailWithLinkDownWhenTheDeviceIsMissing) {
    TempDir dir;
    DaemonProcess daemon(dir, {"--device", dir.file("no-such-tty")});
    auto client = connect_when_ready(daemon.socket());
    const auto s = client.status();
    EXPECT_NE(s.link.state, "up");
    EXPECT_FALSE(s.device_open);
    EXPECT_EQ(error_code_of([&] { client.attitude(); }), -32000) << "no sample yet";
    EXPECT_EQ(error_code_of([&] { client.center(); }), -32000);
    EXPECT_EQ(error_code_of([&] { client.stop(); }), -32000);
    EXPECT_EQ(error_code_of([&] { client.photo(); }), -32000);
}

TEST(ClientTransport, ConnectingToNoDaemonIsATransportError) {
    TempDir dir;
    try {
        gc::Client::connect(dir.file("absent.sock"));
        FAIL() << "connected to nothing";
    } catch (const gc::Error& e) {
        EXPECT_TRUE(e.transport());
        EXPECT_EQ(e.code(), -1);
        EXPECT_NE(e.message().find("absent.sock"), std::string::npos) << e.message();
    }
}

TEST_F(ClientErrors, DaemonGoingAwayIsATransportErrorAndConnectWorksAfterARestart) {
    client().subscribe({"attitude"}, 10);
    daemon_->process().signal(SIGTERM);
    ASSERT_TRUE(daemon_->process().wait().has_value());
    EXPECT_EQ(error_code_of([&] {
                  while (true) {
                      client().next_notification(1s);  // drains what was sent, then breaks
                  }
              }),
              -1);
    EXPECT_FALSE(client().connected());
    EXPECT_EQ(error_code_of([&] { client().status(); }), -1) << "stays broken";

    daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"});
    auto again = connect_when_ready(socket());
    EXPECT_TRUE(link_is(again, "up"));
    EXPECT_EQ(again.status().api_version, 1);
}

TEST_F(ClientErrors, MovedFromAndClosedClientsRefuseCalls) {
    gc::Client moved = std::move(client());
    EXPECT_FALSE(client().connected());
    EXPECT_EQ(error_code_of([&] { client().status(); }), -1) << "moved from";
    EXPECT_EQ(moved.status().link.state, "up") << "the connection moved with it";
    client() = std::move(moved);
    client().close();
    EXPECT_FALSE(client().connected());
    EXPECT_EQ(error_code_of([&] { client().status(); }), -1);
}

}  // namespace
}  // namespace gport::testing
