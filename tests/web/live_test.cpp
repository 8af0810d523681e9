// The live WebSocket: hello, attitude and status; a jog that moves gportd
// and a stop or a close that stops it; gportd going away and coming back;
// a browser that never reads leaving gport-web's memory bounded.
#include <boost/beast/websocket.hpp>
#include <csignal>
#include <fstream>

#include "web_fixture.hpp"

namespace gport::testing {
namespace {

using nlohmann::json;

class WebLive : public WebTest {
  protected:
    void SetUp() override {
        WebTest::SetUp();
        ASSERT_TRUE(start_web());
        ASSERT_TRUE(connected());
    }

    bool moving() {
        const auto motion = gportd_status().at("motion");
        return motion.is_object() && motion.value("mode", "") == "speed";
    }

    long rss_kib() const {
        std::ifstream status("/proc/" + std::to_string(web_->pid()) + "/status");
        std::string line;
        while (std::getline(status, line)) {
            if (line.starts_with("VmRSS:")) {
                return std::stol(line.substr(6));
            }
        }
        return -1;
    }
};

void send(WebSocket& ws, const std::string& text) {
    ws.write(boost::asio::buffer(text));
}

TEST_F(WebLive, HelloThenAttitudeAndStatus) {
    auto ws = live_as();
    const auto hello = next(*ws);
    ASSERT_TRUE(hello);
    EXPECT_EQ(hello->at("method"), "hello");
    EXPECT_EQ(hello->at("params").at("role"), "control");
    const auto attitude = next_method(*ws, "attitude");
    ASSERT_TRUE(attitude);
    EXPECT_EQ(attitude->at("jsonrpc"), "2.0");
    EXPECT_TRUE(attitude->at("params").contains("imu"));
    const auto status = next_method(*ws, "status");
    ASSERT_TRUE(status);
    EXPECT_EQ(status->at("params").at("link").at("state"), "up");
}

TEST_F(WebLive, AJogMovesTheGimbalAndAStopStopsIt) {
    auto ws = live_as();
    ASSERT_TRUE(next_method(*ws, "hello"));
    send(*ws, R"({"type":"jog","pitch":0,"yaw":20,"roll":0})");
    EXPECT_TRUE(eventually([&] { return moving(); }, 5s));
    const auto motion = gportd_status().at("motion");
    EXPECT_EQ(motion.at("speed").at("yaw"), 20.0);
    send(*ws, R"({"type":"stop"})");
    EXPECT_TRUE(eventually([&] { return !gportd_status().at("motion").is_object(); }, 5s));
}

// A logout ends the session for good: a live socket opened with its cookie
// (a stolen one, say) can no longer jog, and is closed when it tries. A stop
// is still taken.
TEST_F(WebLive, ALogoutEndsTheJogsOfTheSocketsOfItsSession) {
    const auto login = request(http::verb::get, "/?token=" + kControlToken);
    const std::string set(login[http::field::set_cookie]);
    const auto cookie = set.substr(0, set.find(';'));
    ASSERT_TRUE(cookie.starts_with("gport_session=")) << set;
    auto ws = live({{"Cookie", cookie}});
    ASSERT_TRUE(next_method(*ws, "hello"));
    send(*ws, R"({"type":"stop"})");
    ASSERT_EQ(
        request(http::verb::post, "/logout", {{"Cookie", cookie}, {"Origin", "http://" + host()}})
            .result(),
        http::status::see_other);
    send(*ws, R"({"type":"jog","yaw":20})");
    // Attitude and status until the close, for 10 s at most.
    for (const auto end = std::chrono::steady_clock::now() + 10s;
         std::chrono::steady_clock::now() < end && next(*ws);) {
    }
    EXPECT_EQ(ws->reason().code, boost::beast::websocket::close_code::policy_error);
    EXPECT_NE(std::string(ws->reason().reason.c_str()).find("logged out"), std::string::npos)
        << ws->reason().reason.c_str();
    std::this_thread::sleep_for(300ms);
    EXPECT_FALSE(moving()) << "the jog of a logged-out session moved the gimbal";
}

TEST_F(WebLive, ClosingAJoggingSocketStopsTheGimbal) {
    ASSERT_EQ(gportd_->call("subscribe", {{"topics", {"motion"}}}).count("result"), 1U);
    auto ws = live_as();
    ASSERT_TRUE(next_method(*ws, "hello"));
    send(*ws, R"({"type":"jog","yaw":-15})");
    ASSERT_TRUE(eventually([&] { return moving(); }, 5s));
    ws->close(boost::beast::websocket::close_code::normal);
    // Ended by gport-web's stop, not by the lease running out.
    std::optional<json> ended;
    while (auto event = gportd_->notification("motion", 5s)) {
        if (event->at("params").value("change", "") == "ended") {
            ended = event;
            break;
        }
    }
    ASSERT_TRUE(ended);
    EXPECT_EQ(ended->at("params").at("reason"), "stop") << ended->dump();
}

TEST_F(WebLive, GportdGoingAwayAndComingBackIsToldToTheBrowsers) {
    auto ws = live_as();
    ASSERT_TRUE(next_method(*ws, "attitude"));
    daemon_.reset();  // gportd stopped
    const auto gone = next_method(*ws, "gportd");
    ASSERT_TRUE(gone);
    EXPECT_EQ(gone->at("params").at("connected"), false);
    EXPECT_EQ(gone->at("params").at("reason").get<std::string>().find('/'), std::string::npos);
    EXPECT_EQ(get("/api/status").result(), http::status::bad_gateway);
    daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"});
    const auto back = next_method(*ws, "gportd");
    ASSERT_TRUE(back);
    EXPECT_EQ(back->at("params").at("connected"), true);
    EXPECT_TRUE(next_method(*ws, "attitude"));
}

// Its log says when gportd goes away and when it is back, in the
// "time [level] text" lines of gportd's logger (the journal under systemd).
TEST(WebLog, GportdGoingAwayAndComingBackAreLogged) {
    TempDir dir;
    auto daemon = std::make_unique<DaemonProcess>(dir, std::vector<std::string>{"--simulate"});
    ASSERT_TRUE(Client(daemon->socket()).connected()) << "gportd listening before gport-web starts";
    const auto token_file = dir.file("token");
    write_token_file(token_file, "control:" + kControlToken + "\n", 0600);
    Process web({"/bin/sh", "-c",
                 std::string("exec ") + GPORT_WEB_PATH + " --listen 127.0.0.1:0 --socket " +
                     daemon->socket() + " --token-file " + token_file + " 2>&1"});
    const auto logged = [&](const std::string& level, const std::string& text) {
        return web
            .wait_line([&](const std::string& l) {
                return l.find("[" + level + "] " + text) != std::string::npos;
            })
            .has_value();
    };
    EXPECT_TRUE(logged("info", "connected to gportd on " + daemon->socket()));
    const auto socket = daemon->socket();
    daemon.reset();
    EXPECT_TRUE(logged("warning", "gportd not reachable: "));
    daemon = std::make_unique<DaemonProcess>(dir, std::vector<std::string>{"--simulate"});
    EXPECT_TRUE(logged("info", "gportd reachable again on " + socket));
}

TEST_F(WebLive, SigtermClosesTheSocketsAndExitsWithZero) {
    auto ws = live_as();
    ASSERT_TRUE(next_method(*ws, "attitude"));
    auto idle = live_as(kViewToken, 4096);
    web_->signal(SIGTERM);
    EXPECT_EQ(web_->wait(), 0);
    while (next(*ws)) {
    }
}

TEST_F(WebLive, ABrowserThatNeverReadsLeavesTheMemoryBounded) {
    auto reader = live_as();
    ASSERT_TRUE(next_method(*reader, "attitude"));
    const long before = rss_kib();
    ASSERT_GT(before, 0);
    std::vector<std::unique_ptr<WebSocket>> stalled;
    for (int i = 0; i < 8; ++i) {
        stalled.push_back(live_as(kViewToken, 4096));  // never read again
    }
    std::this_thread::sleep_for(10s);
    const long after = rss_kib();
    EXPECT_LT(after - before, 16 * 1024) << before << " KiB before, " << after << " KiB after";
    // The reading socket still gets fresh samples.
    EXPECT_TRUE(next_method(*reader, "attitude"));
    EXPECT_TRUE(next_method(*reader, "status"));
}

}  // namespace
}  // namespace gport::testing
