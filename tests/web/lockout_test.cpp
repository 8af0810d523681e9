// No lock-out (issue 42, item 2): wrong tokens from one address cost that
// address, never a valid token or session; a cross-site page can neither
// spend the failures nor log a browser in; idle and slow connections from
// one address leave the operator's page, its stop and a new login working.
// Other peers are other 127/8 source addresses (all of them this host).
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <boost/asio/write.hpp>
#include <thread>

#include "web_fixture.hpp"

namespace gport::testing {
namespace {

using boost::asio::ip::tcp;
using nlohmann::json;

const std::string kWrong = "wrong-token-0123456789abcdef";

class WebLockout : public WebTest {
  protected:
    // gportd on gport-sim (its trace shows the speeds sent to the gimbal).
    void SetUp() override {
        sim_ = std::make_unique<SimProcess>(dir_);
        daemon_ = std::make_unique<DaemonProcess>(
            dir_, std::vector<std::string>{"--device", sim_->link()});
        gportd_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(gportd_->connected());
        ASSERT_TRUE(link_up(*gportd_));
        token_file_ = dir_.file("token");
        write_token_file(token_file_, "control:" + kControlToken + "\nview:" + kViewToken + "\n",
                         0600);
        ASSERT_TRUE(start_web());
        ASSERT_TRUE(connected());
    }

    void TearDown() override {
        web_.reset();
        daemon_.reset();  // before the gimbal it drives
    }

    // The session cookie ("gport_session=...") of a login by `/?token=`
    // from `from`, or "" when refused.
    std::string login_from(const std::string& from, Headers headers = {}) {
        const auto response =
            request_from(from, http::verb::get, "/?token=" + kControlToken, std::move(headers));
        const std::string cookie(response[http::field::set_cookie]);
        return response.result() == http::status::see_other ? cookie.substr(0, cookie.find(';'))
                                                            : "";
    }

    HttpResponse wrong_from(const std::string& from) {
        return request_from(from, http::verb::get, "/api/status",
                            {{"Authorization", "Bearer " + kWrong}});
    }

    // A motion through gportd, then `stop` (true when it answered 200): true
    // when the motion ended and a zero speed reached the gimbal.
    bool stops(const std::function<bool()>& stop) {
        const auto reply = gportd_->call("speed", {{"yaw", 15}, {"duration_ms", 30000}});
        if (!reply.contains("result") || !stop()) {
            return false;
        }
        return sim_->wait_speed({0, 0, 0}) &&
               eventually([&] { return !gportd_status().at("motion").is_object(); }, 5s);
    }

    bool stop_with(const std::string& cookie) {
        return request(http::verb::post, "/api/stop", {{"Cookie", cookie}}).result() ==
               http::status::ok;
    }

    std::unique_ptr<SimProcess> sim_;
};

TEST_F(WebLockout, WrongTokensCostTheirAddressOnlyAndNeverAValidLogin) {
    const auto cookie = login_from("127.0.0.1");
    ASSERT_FALSE(cookie.empty());
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(wrong_from("127.0.0.2").result(), http::status::unauthorized);
    }
    const auto started = std::chrono::steady_clock::now();
    const auto blocked = wrong_from("127.0.0.2");
    EXPECT_EQ(blocked.result(), http::status::too_many_requests);
    const auto retry = std::stoi(std::string(blocked[http::field::retry_after]));
    EXPECT_GT(retry, 0);
    EXPECT_LE(retry, 60);
    EXPECT_GE(std::chrono::steady_clock::now() - started, 900ms);  // the tarpit
    EXPECT_EQ(
        request_from("127.0.0.2", http::verb::post, "/login",
                     {{"Content-Type", "application/x-www-form-urlencoded"}}, "token=" + kWrong)
            .result(),
        http::status::too_many_requests);
    // Valid tokens and sessions from anywhere, the guessing address included.
    EXPECT_FALSE(login_from("127.0.0.1").empty());
    EXPECT_FALSE(login_from("127.0.0.2").empty());
    EXPECT_EQ(request_from("127.0.0.2", http::verb::get, "/api/status",
                           {{"Authorization", "Bearer " + kControlToken}})
                  .result(),
              http::status::ok);
    EXPECT_EQ(get("/api/status").result(), http::status::ok);
    // Another address still has its own failures (401, not 429).
    EXPECT_EQ(wrong_from("127.0.0.3").result(), http::status::unauthorized);
    EXPECT_TRUE(stops([&] { return stop_with(cookie); })) << "no zero speed reached the gimbal";
}

TEST_F(WebLockout, ACrossSiteLoginCountsNothingAndLogsNobodyIn) {
    const Headers cross = {{"Sec-Fetch-Site", "cross-site"}};
    for (int i = 0; i < 10; ++i) {
        const auto response = request(http::verb::get, "/?token=" + kWrong, cross);
        EXPECT_EQ(response.result(), http::status::forbidden);
    }
    for (const char* site : {"cross-site", "same-site", "Cross-Site"}) {
        const auto response =
            request(http::verb::get, "/?token=" + kControlToken, {{"Sec-Fetch-Site", site}});
        EXPECT_EQ(response.result(), http::status::forbidden) << site;
        EXPECT_EQ(response[http::field::set_cookie], "") << site;
    }
    const Headers form = {{"Content-Type", "application/x-www-form-urlencoded"},
                          {"Origin", "http://evil.example"}};
    const auto posted = request(http::verb::post, "/login", form, "token=" + kControlToken);
    EXPECT_EQ(posted.result(), http::status::forbidden);
    EXPECT_EQ(posted[http::field::set_cookie], "");
    // Nothing was counted: this address still has all its failures, and
    // the browser's own page, or curl without the header, logs in.
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(wrong_from("127.0.0.1").result(), http::status::unauthorized) << i;
    }
    EXPECT_FALSE(login_from("127.0.0.1", {{"Sec-Fetch-Site", "same-origin"}}).empty());
    EXPECT_FALSE(login_from("127.0.0.1", {{"Sec-Fetch-Site", "none"}}).empty());
}

// Raises this process's descriptor limit to `wanted` (or the hard limit).
void raise_descriptors(rlim_t wanted) {
    rlimit limit{};
    ::getrlimit(RLIMIT_NOFILE, &limit);
    if (limit.rlim_cur < wanted) {
        limit.rlim_cur = std::min(wanted, limit.rlim_max);
        ::setrlimit(RLIMIT_NOFILE, &limit);
    }
}

// True when the server closed the connection (after a 503 or nothing),
// within a few seconds.
bool closed_by_server(tcp::socket& socket) {
    timeval tv{2, 0};
    ::setsockopt(socket.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    char chunk[512];
    boost::system::error_code ec;
    for (int i = 0; i < 8; ++i) {
        socket.read_some(boost::asio::buffer(chunk), ec);
        if (ec == boost::asio::error::eof || ec == boost::asio::error::connection_reset) {
            return true;
        }
        if (ec) {
            return false;  // the receive timeout: still open
        }
    }
    return false;
}

TEST_F(WebLockout, IdleAndSlowConnectionsLeaveTheOperatorsPageAndStopWorking) {
    raise_descriptors(4096);
    const auto cookie = login_from("127.0.0.1");
    ASSERT_FALSE(cookie.empty());
    auto ws = live({{"Cookie", cookie}, {"Origin", "http://" + host()}});
    ASSERT_TRUE(next_method(*ws, "hello"));

    std::vector<tcp::socket> idle;
    for (int i = 0; i < 1000; ++i) {
        idle.push_back(open_from("127.0.0.2"));
    }
    for (const char* from : {"127.0.0.4", "127.0.0.5", "127.0.0.6"}) {
        for (int i = 0; i < 16; ++i) {
            idle.push_back(open_from(from));
        }
    }
    std::vector<tcp::socket> slow;
    for (int i = 0; i < 16; ++i) {
        slow.push_back(open_from("127.0.0.3"));
    }
    std::atomic<bool> done = false;
    std::thread slowloris([&] {
        const std::string header = "GET / HTTP/1.1\r\nHost: " + host() + "\r\n";
        for (std::size_t at = 0; !done && at < header.size(); ++at) {
            for (auto& socket : slow) {
                boost::system::error_code ignored;
                boost::asio::write(socket, boost::asio::buffer(&header[at], 1), ignored);
            }
            std::this_thread::sleep_for(1s);
        }
    });
    std::this_thread::sleep_for(500ms);

    // The open page's stop, its WebSocket's stop, a new login elsewhere.
    EXPECT_TRUE(stops([&] { return stop_with(cookie); })) << "POST /api/stop";
    EXPECT_TRUE(stops([&] {
        ws->write(boost::asio::buffer(std::string(R"({"type":"stop"})")));
        return true;
    })) << "the WebSocket's stop";
    EXPECT_FALSE(login_from("127.0.0.7").empty());
    EXPECT_EQ(request_from("127.0.0.8", http::verb::get, "/").result(), http::status::ok);

    // The idle and slow ones are closed by the first request's deadline.
    std::this_thread::sleep_for(5s);
    done = true;
    slowloris.join();
    int open = 0;
    for (auto* group : {&idle, &slow}) {
        for (auto& socket : *group) {
            open += closed_by_server(socket) ? 0 : 1;
        }
    }
    EXPECT_EQ(open, 0);
    EXPECT_TRUE(stops([&] { return stop_with(cookie); })) << "POST /api/stop afterwards";
}

TEST_F(WebLockout, ManyFailingAddressesMeetTheCeilingButNotAValidToken) {
    // 12 addresses x 5 failures: the ceiling across all addresses (60).
    for (int a = 10; a < 22; ++a) {
        for (int i = 0; i < 5; ++i) {
            EXPECT_EQ(wrong_from("127.0.1." + std::to_string(a)).result(),
                      http::status::unauthorized);
        }
    }
    const auto fresh = wrong_from("127.0.2.1");
    EXPECT_EQ(fresh.result(), http::status::too_many_requests);
    EXPECT_FALSE(fresh[http::field::retry_after].empty());
    EXPECT_FALSE(login_from("127.0.2.1").empty());
    EXPECT_EQ(request_from("127.0.2.2", http::verb::get, "/api/status",
                           {{"Authorization", "Bearer " + kViewToken}})
                  .result(),
              http::status::ok);
}

}  // namespace
}  // namespace gport::testing
