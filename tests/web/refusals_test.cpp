// gport-web's refusals first: no login, a foreign Host or Origin, oversize
// requests and frames, a token file others may read, wrong tokens beyond
// the failures allowed, a view login that tries to move the gimbal, too
// many connections from one address (lockout_test.cpp has the rest).
#include <sys/stat.h>
#include <unistd.h>

#include <boost/beast/websocket.hpp>
#include <fstream>

#include "web_fixture.hpp"

namespace gport::testing {
namespace {

using nlohmann::json;
namespace websocket = boost::beast::websocket;

const std::vector<std::string> kApiPaths = {
    "/api/status",       "/api/settings",         "/api/limits", "/api/version", "/api/captures",
    "/api/captures.csv", "/api/captures.geojson", "/api/live",   "/api/stop"};

Headers upgrade_headers(const std::string& host) {
    return {{"Connection", "Upgrade"},
            {"Upgrade", "websocket"},
            {"Sec-WebSocket-Version", "13"},
            {"Sec-WebSocket-Key", "dGhlIHNhbXBsZSBub25jZQ=="},
            {"Origin", "http://" + host}};
}

void expect_no_data(const HttpResponse& response) {
    EXPECT_EQ(response.result(), http::status::unauthorized);
    EXPECT_EQ(response.body().find("daemon_version"), std::string::npos);
    EXPECT_EQ(response.body().find("index,utc"), std::string::npos);
    EXPECT_EQ(json::parse(response.body()).at("error").at("code"), 401);
}

class WebRefusals : public WebTest {
  protected:
    void SetUp() override {
        WebTest::SetUp();
        ASSERT_TRUE(start_web());
        ASSERT_TRUE(connected());
    }
};

TEST_F(WebRefusals, EveryApiPathWithoutAValidLoginIs401WithNoData) {
    for (const auto& path : kApiPaths) {
        SCOPED_TRACE(path);
        expect_no_data(request(http::verb::get, path));
        expect_no_data(request(http::verb::get, path, {{"Cookie", "gport_session=0123abcd"}}));
        expect_no_data(request(http::verb::post, path, {{"Cookie", "gport_session="}}));
    }
    // Wrong tokens (each a failed login: the fifth is the last before 429).
    expect_no_data(get("/api/status", "wrong-token-0123456789abcdef"));
    expect_no_data(get("/api/captures.csv", kControlToken.substr(1)));
    expect_no_data(request(http::verb::post, "/api/stop", {{"Authorization", "Bearer "}}));
    expect_no_data(request(http::verb::get, "/api/live", upgrade_headers(host())));
    auto wrong = upgrade_headers(host());
    wrong["Authorization"] = "Bearer " + kViewToken + "x";
    expect_no_data(request(http::verb::get, "/api/live", wrong));
    EXPECT_THROW(live({{"Origin", "http://" + host()}}), boost::system::system_error);
    // The page's other files need the login; / answers with the login page.
    EXPECT_EQ(request(http::verb::get, "/index.html").result(), http::status::unauthorized);
    EXPECT_EQ(request(http::verb::get, "/").result(), http::status::ok);
}

TEST_F(WebRefusals, AForeignHostIsRefusedEvenWithTheToken) {
    for (const auto& foreign :
         {"evil.example:" + std::to_string(port_), std::string("evil.example"),
          std::string("127.0.0.1:1"), std::string("")}) {
        SCOPED_TRACE(foreign);
        const auto response =
            request(http::verb::get, "/api/status",
                    {{"Host", foreign}, {"Authorization", "Bearer " + kControlToken}});
        EXPECT_EQ(response.result(), http::status::forbidden);
        EXPECT_EQ(response.body().find("daemon_version"), std::string::npos);
    }
    EXPECT_EQ(request(http::verb::get, "/api/status",
                      {{"Host", "localhost:" + std::to_string(port_)},
                       {"Authorization", "Bearer " + kControlToken}})
                  .result(),
              http::status::ok);
}

TEST_F(WebRefusals, AnUpgradeFromAForeignOriginIsRefused) {
    auto headers = upgrade_headers(host());
    headers["Authorization"] = "Bearer " + kControlToken;
    headers["Origin"] = "http://evil.example";
    EXPECT_EQ(request(http::verb::get, "/api/live", headers).result(), http::status::forbidden);
    headers["Origin"] = "null";
    EXPECT_EQ(request(http::verb::get, "/api/live", headers).result(), http::status::forbidden);
    EXPECT_THROW(live({{"Authorization", "Bearer " + kControlToken},
                       {"Origin", "http://evil.example:" + std::to_string(port_)}}),
                 boost::system::system_error);
    EXPECT_NO_THROW(live_as(kControlToken));
}

TEST_F(WebRefusals, OversizeHeadersAndBodiesAre431And413) {
    const std::string pad(9 * 1024, 'x');
    const auto big_header =
        raw("GET /api/status HTTP/1.1\r\nHost: " + host() + "\r\nX-Pad: " + pad + "\r\n\r\n");
    EXPECT_TRUE(big_header.starts_with("HTTP/1.1 431")) << big_header.substr(0, 80);
    const std::string body(17 * 1024, ' ');
    const auto big_body = raw(
        "POST /api/angle HTTP/1.1\r\nHost: " + host() + "\r\nAuthorization: Bearer " +
        kControlToken + "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
    EXPECT_TRUE(big_body.starts_with("HTTP/1.1 413")) << big_body.substr(0, 80);
    EXPECT_FALSE(gportd_status().at("motion").is_object());
}

TEST_F(WebRefusals, AnOversizeWebSocketMessageClosesTheSocket) {
    auto ws = live_as();
    ASSERT_TRUE(next_method(*ws, "hello"));
    ws->write(boost::asio::buffer(std::string(5 * 1024, 'x')));
    while (next(*ws)) {
    }
    EXPECT_EQ(ws->reason().code, websocket::close_code::too_big);
}

TEST_F(WebRefusals, TooManyMessagesASecondCloseTheSocketWith1008) {
    auto ws = live_as();
    ASSERT_TRUE(next_method(*ws, "hello"));
    boost::system::error_code ec;
    for (int i = 0; i < 100 && !ec; ++i) {
        ws->write(boost::asio::buffer(std::string(R"({"type":"ping"})")), ec);
    }
    while (next(*ws)) {
    }
    EXPECT_EQ(ws->reason().code, websocket::close_code::policy_error);
}

TEST_F(WebRefusals, WrongTokensBeyondTheFailuresAre429ButTheRightOneGetsIn) {
    const Headers form = {{"Content-Type", "application/x-www-form-urlencoded"}};
    const auto before = request(http::verb::get, "/?token=" + kViewToken);
    const std::string cookie(before[http::field::set_cookie]);
    ASSERT_FALSE(cookie.empty());
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(
            request(http::verb::post, "/login", form, "token=wrong-token-0123456789").result(),
            http::status::unauthorized);
    }
    // Wrong tokens, in the form or the Authorization header, are 429.
    const auto blocked = request(http::verb::post, "/login", form, "token=wrong");
    EXPECT_EQ(blocked.result(), http::status::too_many_requests);
    EXPECT_GT(std::stoi(std::string(blocked[http::field::retry_after])), 0);
    EXPECT_EQ(blocked[http::field::set_cookie], "");
    EXPECT_EQ(get("/api/status", "wrong-token-0123456789").result(),
              http::status::too_many_requests);
    // The right ones are never refused (issue 42: no lock-out), nor are the
    // sessions opened before.
    const auto login = request(http::verb::post, "/login", form, "token=" + kControlToken);
    EXPECT_EQ(login.result(), http::status::see_other);
    EXPECT_NE(login[http::field::set_cookie], "");
    EXPECT_EQ(request(http::verb::get, "/?token=" + kControlToken).result(),
              http::status::see_other);
    EXPECT_EQ(get("/api/status").result(), http::status::ok);
    EXPECT_EQ(
        request(http::verb::get, "/api/status", {{"Cookie", cookie.substr(0, cookie.find(';'))}})
            .result(),
        http::status::ok);
}

TEST_F(WebRefusals, AViewLoginCanReadButNeitherPostNorJog) {
    EXPECT_EQ(get("/api/status", kViewToken).result(), http::status::ok);
    EXPECT_EQ(get("/api/limits", kViewToken).result(), http::status::ok);
    // Reading the settings is an exchange with the gimbal: gportd refuses it
    // to its own read-only clients, and so does gport-web to a view login.
    const auto settings = get("/api/settings", kViewToken);
    EXPECT_EQ(settings.result(), http::status::forbidden);
    EXPECT_NE(settings.body().find("a view login cannot read the gimbal's settings"),
              std::string::npos)
        << settings.body();
    EXPECT_EQ(get("/api/settings").result(), http::status::ok) << "a control login reads them";
    for (const char* path : {"/api/stop", "/api/photo", "/api/center", "/api/angle"}) {
        EXPECT_EQ(post(path, "{}", kViewToken).result(), http::status::forbidden) << path;
    }
    auto ws = live_as(kViewToken);
    const auto hello = next_method(*ws, "hello");
    ASSERT_TRUE(hello);
    EXPECT_EQ(hello->at("params").at("role"), "view");
    ws->write(boost::asio::buffer(std::string(R"({"type":"jog","yaw":20})")));
    const auto error = next_method(*ws, "error");
    ASSERT_TRUE(error);
    EXPECT_NE(error->at("params").at("message").get<std::string>().find("view"), std::string::npos);
    EXPECT_FALSE(gportd_status().at("motion").is_object());
}

TEST_F(WebRefusals, ConnectionsBeyondTheLimitOfAnAddressGet503) {
    std::vector<boost::asio::ip::tcp::socket> held;
    for (int i = 0; i < 16; ++i) {
        held.push_back(open_from("127.0.0.1"));
    }
    std::this_thread::sleep_for(300ms);
    const auto busy = raw("GET / HTTP/1.1\r\nHost: " + host() + "\r\n\r\n");
    EXPECT_TRUE(busy.starts_with("HTTP/1.1 503")) << busy.substr(0, 80);
    EXPECT_NE(busy.find("from your address"), std::string::npos) << busy;
    EXPECT_EQ(request_from("127.0.0.2", http::verb::get, "/").result(), http::status::ok);
    held.clear();
    EXPECT_TRUE(eventually([&] { return get("/api/status").result() == http::status::ok; }));
}

class WebTokenFile : public WebTest {};

TEST_F(WebTokenFile, AFileOthersMayReadIsRefusedNamingTheFileAndMode) {
    write_token_file(token_file_, "control:" + kControlToken + "\n", 0644);
    Process web({"/bin/sh", "-c",
                 std::string("exec ") + GPORT_WEB_PATH + " --listen 127.0.0.1:0 --socket " +
                     daemon_->socket() + " --token-file " + token_file_ + " 2>&1"});
    const auto line = web.next_line();
    ASSERT_TRUE(line);
    EXPECT_NE(line->find(token_file_), std::string::npos) << *line;
    EXPECT_NE(line->find("0644"), std::string::npos) << *line;
    EXPECT_EQ(web.wait(), 66);
}

// The token of a file gport-web created ("control:TOKEN").
std::string read_token(const std::string& path) {
    std::ifstream file(path);
    std::string line;
    std::getline(file, line);
    return line.substr(line.find(':') + 1);
}

TEST_F(WebTokenFile, AMissingFileIsCreatedWithARandomTokenAndTheFirstRunUrl) {
    const auto path = dir_.file("state/token");
    ASSERT_TRUE(start_web({"--token-file", path}));
    const auto created = web_->next_line();
    ASSERT_TRUE(created);
    EXPECT_EQ(*created, "gport-web: created " + path + " with a control token");
    const auto line = web_->next_line();
    ASSERT_TRUE(line);
    // The link logs in once (a one-time code, not the token: docs/web.md,
    // "Logging in at the field").
    const std::string prefix = "gport-web: open http://" + host() + "/?code=";
    ASSERT_TRUE(line->starts_with(prefix)) << *line;
    EXPECT_NE(line->find("the tokens are in " + path), std::string::npos) << *line;
    const auto token = read_token(path);
    EXPECT_EQ(line->find(token), std::string::npos) << "the token itself is not printed";
    struct stat st {};
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600U);
    EXPECT_TRUE(connected(token));
}

TEST_F(WebTokenFile, AFifoIsRefusedAtOnceInsteadOfWaitedOn) {
    ASSERT_EQ(::unlink(token_file_.c_str()), 0);  // the fixture's file, replaced by a FIFO
    ASSERT_EQ(::mkfifo(token_file_.c_str(), 0600), 0);
    Process web({"/bin/sh", "-c",
                 std::string("exec ") + GPORT_WEB_PATH + " --listen 127.0.0.1:0 --socket " +
                     daemon_->socket() + " --token-file " + token_file_ + " 2>&1"});
    const auto line = web.next_line(20s);
    ASSERT_TRUE(line) << "gport-web hung on the FIFO";
    EXPECT_NE(line->find(token_file_), std::string::npos) << *line;
    EXPECT_NE(line->find("must be a regular file"), std::string::npos) << *line;
    EXPECT_EQ(web.wait(20s), 66);
}

TEST_F(WebTokenFile, ATokenGivenTwiceIsRefusedNamingTheLine) {
    write_token_file(token_file_,
                     "control:" + kControlToken + "\n# the same one\nview:" + kControlToken + "\n",
                     0600);
    Process web({"/bin/sh", "-c",
                 std::string("exec ") + GPORT_WEB_PATH + " --listen 127.0.0.1:0 --socket " +
                     daemon_->socket() + " --token-file " + token_file_ + " 2>&1"});
    const auto line = web.next_line();
    ASSERT_TRUE(line);
    EXPECT_NE(line->find("line 3: the same token as an earlier line (as control)"),
              std::string::npos)
        << *line;
    EXPECT_EQ(web.wait(), 66);
}

TEST_F(WebTokenFile, TheDirectoriesMadeForANewFileAreTheUsersAlone) {
    const auto path = dir_.file("made/for/token");
    ASSERT_TRUE(start_web({"--token-file", path}));
    for (const auto& made : {dir_.file("made"), dir_.file("made/for")}) {
        struct stat st {};
        ASSERT_EQ(::stat(made.c_str(), &st), 0) << made;
        EXPECT_EQ(st.st_mode & 0777, 0700U) << made;
    }
}

TEST_F(WebRefusals, TheBearerSchemeIsCaseInsensitive) {
    for (const auto& scheme : {"bearer ", "BEARER ", "Bearer   ", "bEaReR "}) {
        SCOPED_TRACE(scheme);
        EXPECT_EQ(request(http::verb::get, "/api/status",
                          {{"Authorization", std::string(scheme) + kControlToken}})
                      .result(),
                  http::status::ok);
    }
    EXPECT_EQ(
        request(http::verb::get, "/api/status", {{"Authorization", "Bearerx " + kControlToken}})
            .result(),
        http::status::unauthorized);
}

class WebListen : public WebTest {};

// --listen 0.0.0.0: the links printed are the interfaces' real addresses (an
// http://0.0.0.0:PORT/ link opens nothing), and an IP literal is a Host
// only when it is one of them.
TEST_F(WebListen, OnEveryAddressItPrintsRealLinksAndAcceptsOnlyThemAsHost) {
    web_ = std::make_unique<Process>(
        std::vector<std::string>{GPORT_WEB_PATH, "--socket", daemon_->socket(), "--listen",
                                 "0.0.0.0:0", "--token-file", dir_.file("new-token")});
    std::vector<std::string> lines;
    while (auto line = web_->next_line(lines.empty() ? 10s : 500ms)) {
        lines.push_back(*line);
    }
    ASSERT_FALSE(lines.empty());
    std::string all;
    for (const auto& l : lines) {
        all += l + "\n";
        EXPECT_EQ(l.find("0.0.0.0"), std::string::npos) << l;
    }
    const std::string loopback = "gport-web: serving http://127.0.0.1:";
    const auto at = all.find(loopback);
    ASSERT_NE(at, std::string::npos) << all;
    port_ = static_cast<unsigned short>(std::stoi(all.substr(at + loopback.size())));
    EXPECT_NE(all.find("gport-web: open http://127.0.0.1:" + std::to_string(port_) + "/?code="),
              std::string::npos)
        << all;
    const auto token = read_token(dir_.file("new-token"));
    const auto status_with = [&](const std::string& host) {
        return request(http::verb::get, "/api/status",
                       {{"Host", host}, {"Authorization", "Bearer " + token}})
            .result();
    };
    EXPECT_EQ(status_with("127.0.0.1:" + std::to_string(port_)), http::status::ok);
    EXPECT_EQ(status_with("localhost:" + std::to_string(port_)), http::status::ok);
    EXPECT_EQ(status_with("203.0.113.9:" + std::to_string(port_)), http::status::forbidden)
        << "an address this machine does not have";
}

}  // namespace
}  // namespace gport::testing
