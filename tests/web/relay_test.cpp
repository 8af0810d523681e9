// The stop comes first (docs/web.md, "The stop comes first"): a browser's
// stop is not held behind other browsers' jogs or reads, gport-web never
// loses its gportd connection to a flood, and what every browser polls
// costs gportd one request a second, not one per browser. (The stop's
// latency at the real line rate under each flood: bench_relay_stop.)
#include <atomic>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <chrono>
#include <cstdio>
#include <set>
#include <thread>

#include "web_fixture.hpp"

namespace gport::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

class WebRelay : public WebTest {
  protected:
    void SetUp() override {
        WebTest::SetUp();
        ASSERT_TRUE(start_web());
        ASSERT_TRUE(connected());
    }
};

// Whether gport-web told this browser that gportd went away.
bool told_gportd_gone(WebSocket& ws) {
    ws.next_layer().non_blocking(true);
    boost::beast::flat_buffer buffer;
    bool gone = false;
    boost::system::error_code ec;
    while (!ec) {
        ws.read(buffer, ec);
        if (ec) {
            break;
        }
        const auto message =
            json::parse(boost::beast::buffers_to_string(buffer.data()), nullptr, false);
        buffer.consume(buffer.size());
        gone = gone || (message.value("method", "") == "gportd" &&
                        !message.at("params").value("connected", true));
    }
    ws.next_layer().non_blocking(false);
    return gone;
}

// Fourteen control browsers jog at 25 messages a second each (under their
// limit of 30; 350 a second together, more than gportd takes from one
// connection): a fifteenth one's stop still reaches gportd within a
// second (the figure is printed), and gport-web keeps its connection. Before
// the command lane, such a stop waited seconds behind the jogs, and a
// later one got 502 as gport-web dropped its gportd connection.
TEST_F(WebRelay, AStopGoesAheadOfEveryOtherBrowsersJogs) {
    ASSERT_EQ(gportd_->call("subscribe", {{"topics", {"motion"}}}).count("result"), 1U);
    std::vector<std::unique_ptr<WebSocket>> joggers;
    for (int i = 0; i < 14; ++i) {
        joggers.push_back(live_as());
        ASSERT_TRUE(next_method(*joggers.back(), "hello"));
    }
    auto probe = live_as();
    ASSERT_TRUE(next_method(*probe, "hello"));
    std::atomic<bool> flooding{true};
    std::thread flood([&] {
        const std::string jog = R"({"type":"jog","yaw":0.2})";
        while (flooding) {
            for (auto& ws : joggers) {
                boost::system::error_code ec;
                ws->write(boost::asio::buffer(jog), ec);
            }
            std::this_thread::sleep_for(40ms);
        }
    });
    std::this_thread::sleep_for(3s);  // the jogs pile up where they can
    double worst_ms = 0;
    for (int i = 0; i < 3; ++i) {
        while (gportd_->notification("motion", 50ms)) {
        }
        const auto sent = Clock::now();
        probe->write(boost::asio::buffer(std::string(R"({"type":"stop"})")));
        bool stopped = false;
        while (auto event = gportd_->notification("motion", 5s)) {
            const auto& params = event->at("params");
            if (params.value("change", "") == "ended" && params.value("reason", "") == "stop") {
                stopped = true;
                break;
            }
        }
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - sent).count();
        worst_ms = std::max(worst_ms, ms);
        EXPECT_TRUE(stopped) << "stop " << i;
        EXPECT_LT(ms, 1000) << "stop " << i << " reached gportd after " << ms << " ms";
        std::this_thread::sleep_for(300ms);
    }
    flooding = false;
    flood.join();
    std::printf("stop through gport-web beside 14 jogging browsers: worst %.1f ms to gportd\n",
                worst_ms);
    EXPECT_FALSE(told_gportd_gone(*probe)) << "gport-web lost gportd under the jogs";
    EXPECT_EQ(post("/api/stop", "").result(), http::status::ok);
}

// A hundred status reads over about two seconds, as browsers poll: gportd
// is asked at most once a second for all of them (one shared snapshot), so
// the answers within a second are one and the same. (Asked each time, its
// counters make nearly every answer a new one.)
TEST_F(WebRelay, BrowsersStatusReadsShareOneSnapshot) {
    std::set<std::string> bodies;
    const auto start = Clock::now();
    for (int i = 0; i < 100; ++i) {
        const auto response = get("/api/status", kViewToken);
        ASSERT_EQ(response.result(), http::status::ok) << response.body();
        bodies.insert(response.body());
        std::this_thread::sleep_for(20ms);
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    std::printf("100 status reads in %.2f s: %zu distinct answers\n", seconds, bodies.size());
    EXPECT_LE(bodies.size(), static_cast<std::size_t>(seconds) + 2);
}

// One address polling past its rate (50 a second, a burst of 100) gets 429
// with Retry-After, as all its logins together; its stop still goes, and
// another address is served.
TEST_F(WebRelay, AnAddressPastItsRateGets429ButItsStopStillGoes) {
    const Headers bearer = {{"Authorization", "Bearer " + kViewToken}};
    const Headers control = {{"Authorization", "Bearer " + kControlToken},
                             {"Content-Type", "application/json"}};
    int refused = 0;
    std::string retry_after;
    for (int i = 0; i < 200 && refused == 0; ++i) {
        const auto response = request_from("127.0.0.7", http::verb::get, "/api/status", bearer);
        if (response.result() == http::status::too_many_requests) {
            ++refused;
            retry_after = std::string(response[http::field::retry_after]);
            EXPECT_NE(response.body().find("too many requests from your address"),
                      std::string::npos)
                << response.body();
        }
    }
    EXPECT_EQ(refused, 1);
    EXPECT_FALSE(retry_after.empty());
    EXPECT_EQ(request_from("127.0.0.7", http::verb::post, "/api/stop", control, "").result(),
              http::status::ok);
    EXPECT_EQ(request_from("127.0.0.8", http::verb::get, "/api/status", bearer).result(),
              http::status::ok);
}

}  // namespace
}  // namespace gport::testing
