// Logging in at the field (docs/web.md): a one-time link printed at every
// start and by --print-url that works once (the address left in the
// browser's history logs no one in), sessions that outlive a restart of
// gport-web, and a login page that names the token file.
#include <sys/stat.h>

#include "web_fixture.hpp"

namespace gport::testing {
namespace {

class WebLogin : public WebTest {
  protected:
    // The path and query of a printed link (http://HOST:PORT/?code=...).
    static std::string target_of(const std::string& link) {
        const auto at = link.find("/?code=");
        const auto end = link.find(' ', at);
        return link.substr(at, end == std::string::npos ? std::string::npos : end - at);
    }

    std::string printed_link() {
        const auto line = web_->wait_line(
            [](const std::string& l) { return l.starts_with("gport-web: open http://"); });
        return line ? target_of(*line) : "";
    }

    // The session cookie a login answer sets ("gport_session=...").
    static std::string cookie_of(const HttpResponse& response) {
        const std::string set(response[http::field::set_cookie]);
        return set.substr(0, set.find(';'));
    }

    http::status status_with_cookie(const std::string& cookie) {
        return request(http::verb::get, "/api/status", {{"Cookie", cookie}}).result();
    }
};

TEST_F(WebLogin, EveryStartPrintsALinkThatLogsInOnce) {
    ASSERT_TRUE(start_web());
    const auto link = printed_link();
    ASSERT_FALSE(link.empty());
    const auto first = request(http::verb::get, link);
    ASSERT_EQ(first.result(), http::status::see_other) << first.body();
    const auto cookie = cookie_of(first);
    EXPECT_TRUE(cookie.starts_with("gport_session=")) << cookie;
    EXPECT_TRUE(eventually([&] { return status_with_cookie(cookie) == http::status::ok; }));
    const auto again = request(http::verb::get, link);
    EXPECT_EQ(again.result(), http::status::unauthorized) << "the link from history";
}

TEST_F(WebLogin, ASessionOutlivesARestartAndALogoutEndsIt) {
    ASSERT_TRUE(start_web());
    ASSERT_TRUE(connected());
    const auto cookie = cookie_of(request(http::verb::get, "/?token=" + kControlToken));
    ASSERT_EQ(status_with_cookie(cookie), http::status::ok);
    struct stat st {};
    ASSERT_EQ(::stat(dir_.file("sessions").c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600U);
    web_.reset();
    ASSERT_TRUE(start_web());
    EXPECT_TRUE(eventually([&] { return status_with_cookie(cookie) == http::status::ok; }))
        << "logged out by the restart";
    const auto origin = "http://" + host();
    EXPECT_EQ(
        request(http::verb::post, "/logout", {{"Cookie", cookie}, {"Origin", origin}}).result(),
        http::status::see_other);
    web_.reset();
    ASSERT_TRUE(start_web());
    EXPECT_EQ(status_with_cookie(cookie), http::status::unauthorized);
}

TEST_F(WebLogin, ALinkUsedStaysUsedAfterARestart) {
    ASSERT_TRUE(start_web());
    const auto link = printed_link();
    ASSERT_EQ(request(http::verb::get, link).result(), http::status::see_other);
    web_.reset();
    ASSERT_TRUE(start_web());
    EXPECT_EQ(request(http::verb::get, link).result(), http::status::unauthorized);
}

TEST_F(WebLogin, PrintUrlPrintsAWorkingLinkAndNeverMakesTheFile) {
    ASSERT_TRUE(start_web());
    const auto listen = "127.0.0.1:" + std::to_string(port_);
    Process print({GPORT_WEB_PATH, "--print-url", "--listen", listen, "--token-file", token_file_});
    const auto line = print.next_line();
    ASSERT_TRUE(line);
    EXPECT_TRUE(line->starts_with("http://" + listen + "/?code=")) << *line;
    EXPECT_EQ(print.wait(), 0);
    EXPECT_EQ(request(http::verb::get, target_of(*line)).result(), http::status::see_other);
    const auto missing = dir_.file("none/token");
    Process refused({"/bin/sh", "-c",
                     std::string("exec ") + GPORT_WEB_PATH + " --print-url --listen " + listen +
                         " --token-file " + missing + " 2>&1"});
    const auto error = refused.next_line();
    ASSERT_TRUE(error);
    EXPECT_NE(error->find("no token file " + missing), std::string::npos) << *error;
    EXPECT_EQ(refused.wait(), 66);
    EXPECT_NE(::access(missing.c_str(), F_OK), 0);
}

TEST_F(WebLogin, TheLoginPageNamesTheTokenFile) {
    ASSERT_TRUE(start_web());
    const auto page = request(http::verb::get, "/");
    ASSERT_EQ(page.result(), http::status::ok);
    EXPECT_NE(page.body().find(R"(<code data-testid="token-file">)" + token_file_ + "</code>"),
              std::string::npos)
        << page.body();
}

}  // namespace
}  // namespace gport::testing
