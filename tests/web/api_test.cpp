// The HTTP API and the login's happy paths: gportd's status passed through,
// /?token= and POST /login setting the session cookie with 303, logout,
// checked bodies, the capture log's page and its streamed downloads (the CSV
// byte for byte gportctl captures --csv's).
#include <fstream>
#include <sstream>

#include "web_fixture.hpp"

namespace gport::testing {
namespace {

using nlohmann::json;

class WebApi : public WebTest {
  protected:
    void SetUp() override {
        WebTest::SetUp();
        ASSERT_TRUE(start_web());
        ASSERT_TRUE(connected());
    }

    // The session id of a Set-Cookie header, checking its attributes.
    static std::string cookie_of(const HttpResponse& response) {
        const std::string cookie(response[http::field::set_cookie]);
        EXPECT_TRUE(cookie.starts_with("gport_session=")) << cookie;
        EXPECT_NE(cookie.find("; HttpOnly"), std::string::npos) << cookie;
        EXPECT_NE(cookie.find("; SameSite=Strict"), std::string::npos) << cookie;
        EXPECT_NE(cookie.find("; Path=/"), std::string::npos) << cookie;
        return cookie.substr(0, cookie.find(';'));
    }
};

TEST_F(WebApi, StatusIsGportdsStatus) {
    const auto response = get("/api/status", kViewToken);
    ASSERT_EQ(response.result(), http::status::ok);
    EXPECT_EQ(response[http::field::content_type], "application/json");
    const auto status = json::parse(response.body());
    EXPECT_EQ(status.at("link").at("state"), "up");
    EXPECT_EQ(status.at("api_version"), gportd_status().at("api_version"));
    const auto version = json::parse(get("/api/version").body());
    EXPECT_EQ(version.at("daemon_version"), status.at("daemon_version"));
    EXPECT_TRUE(version.at("version").is_string());
    EXPECT_EQ(version.at("config_file"), status.at("config_file"));
    EXPECT_TRUE(json::parse(get("/api/limits").body()).is_object());
}

TEST_F(WebApi, TheTokenInTheAddressSetsAStrictHttpOnlyCookieAndRedirects) {
    const auto login = request(http::verb::get, "/?token=" + kControlToken);
    ASSERT_EQ(login.result(), http::status::see_other);
    EXPECT_EQ(login[http::field::location], "/");
    const auto cookie = cookie_of(login);
    EXPECT_EQ(request(http::verb::get, "/api/status", {{"Cookie", cookie}}).result(),
              http::status::ok);

    const auto logout = request(http::verb::post, "/logout", {{"Cookie", cookie}});
    EXPECT_EQ(logout.result(), http::status::see_other);
    EXPECT_EQ(request(http::verb::get, "/api/status", {{"Cookie", cookie}}).result(),
              http::status::unauthorized);
}

TEST_F(WebApi, APostedFormLogsInWithARoleOfItsToken) {
    const auto login =
        request(http::verb::post, "/login", {{"Content-Type", "application/x-www-form-urlencoded"}},
                "token=" + kViewToken);
    ASSERT_EQ(login.result(), http::status::see_other);
    const auto cookie = cookie_of(login);
    EXPECT_EQ(request(http::verb::get, "/api/status", {{"Cookie", cookie}}).result(),
              http::status::ok);
    EXPECT_EQ(request(http::verb::post, "/api/stop", {{"Cookie", cookie}}).result(),
              http::status::forbidden);
}

TEST_F(WebApi, ThePageComesWithItsSecurityHeaders) {
    const auto page = request(http::verb::get, "/");  // no login: the login page
    ASSERT_EQ(page.result(), http::status::ok);
    EXPECT_TRUE(std::string(page[http::field::content_type]).starts_with("text/html"));
    const std::string policy(page["Content-Security-Policy"]);
    EXPECT_NE(policy.find("default-src 'self'"), std::string::npos) << policy;
    EXPECT_NE(policy.find("frame-ancestors 'none'"), std::string::npos) << policy;
    EXPECT_EQ(page["X-Frame-Options"], "DENY");
    EXPECT_EQ(page["X-Content-Type-Options"], "nosniff");
    // A page with an inline <style> allows that style by its hash only.
    if (page.body().find("<style>") != std::string::npos) {
        const auto at = policy.find("style-src 'self' 'sha256-");
        ASSERT_NE(at, std::string::npos) << policy;
        EXPECT_EQ(policy.find('\'', at + 25), at + 25 + 44) << policy;  // 32 bytes in base64
    }
    EXPECT_EQ(policy.find("unsafe-inline"), std::string::npos);
}

TEST_F(WebApi, BodiesAreCheckedNamingTheField) {
    auto response = post("/api/angle", R"({"pitch":"down"})");
    EXPECT_EQ(response.result(), http::status::bad_request);
    EXPECT_NE(response.body().find("pitch"), std::string::npos);
    response = post("/api/angle", R"({"tilt":3})");
    EXPECT_EQ(response.result(), http::status::bad_request);
    EXPECT_NE(response.body().find("tilt"), std::string::npos);
    EXPECT_EQ(post("/api/record", "[true]").result(), http::status::bad_request);
    EXPECT_EQ(get("/api/nothing").result(), http::status::not_found);
    EXPECT_EQ(post("/api/status", "{}").result(), http::status::method_not_allowed);
    // gportd's own refusal of a value out of range: 400 with gportd's code.
    response = post("/api/angle", R"({"pitch":1000})");
    EXPECT_EQ(response.result(), http::status::bad_request);
    EXPECT_EQ(json::parse(response.body()).at("error").at("code"), -32602);
}

TEST_F(WebApi, AngleAndCenterMoveTheGimbal) {
    const auto angle = post("/api/angle", R"({"yaw":10,"wait":true})");
    ASSERT_EQ(angle.result(), http::status::ok) << angle.body();
    EXPECT_EQ(json::parse(angle.body()).at("angle").at("yaw"), 10.0);
    EXPECT_EQ(post("/api/center", R"({"wait":true})").result(), http::status::ok);
    EXPECT_EQ(post("/api/stop", "").result(), http::status::ok);
}

TEST_F(WebApi, TheCaptureLogComesAsAPageAndAsStreamedCsvAndGeoJson) {
    for (int i = 0; i < 3; ++i) {
        ASSERT_EQ(post("/api/photo", "").result(), http::status::ok);
    }
    const auto page = json::parse(get("/api/captures?since=0&limit=2").body());
    EXPECT_EQ(page.at("captures").size(), 2U);
    EXPECT_EQ(get("/api/captures?limit=x").result(), http::status::bad_request);

    const auto csv = get("/api/captures.csv", kViewToken);
    ASSERT_EQ(csv.result(), http::status::ok);
    EXPECT_TRUE(csv.chunked());
    EXPECT_TRUE(csv.body().starts_with("index,utc,kind,imu_roll,"));
    EXPECT_EQ(std::count(csv.body().begin(), csv.body().end(), '\n'), 4);
    EXPECT_NE(csv.body().find("\"photo\""), std::string::npos);

    const auto geojson = get("/api/captures.geojson");
    ASSERT_EQ(geojson.result(), http::status::ok);
    const auto collection = json::parse(geojson.body());
    EXPECT_EQ(collection.at("type"), "FeatureCollection");
    EXPECT_TRUE(collection.at("features").empty());  // no position given with these photos
}

// gportctl captures --csv's stdout as written to a file, byte for byte.
std::string gportctl_csv(const std::string& socket, const std::string& file) {
    Process gportctl({"/bin/sh", "-c", "exec \"$0\" --socket \"$1\" captures --csv > \"$2\"",
                      GPORTCTL_PATH, socket, file});
    EXPECT_EQ(gportctl.wait(20s), 0);
    std::ostringstream bytes;
    bytes << std::ifstream(file, std::ios::binary).rdbuf();
    return bytes.str();
}

// One writer (libgport-client's capture_files.hpp) behind both: the same
// log gives the same bytes, whatever its positions hold.
TEST_F(WebApi, TheCsvDownloadIsGportctlsCsvByteForByte) {
    const json metas[] = {{{"lat", 47.397742}, {"lon", -8.545594}, {"alt_m", 488.2}},
                          {{"lat", "47.5"}, {"lon", 8.5}},
                          {{"lat", -33.9}, {"note", "say \"cheese\", twice\r\n=1"}},
                          {{"lat", 1e-7}, {"lon", -180}, {"alt_m", -0.5}}};
    for (const auto& meta : metas) {
        ASSERT_EQ(gportd_->call("photo", {{"meta", meta}}).at("result").at("sent"), true);
    }
    const auto csv = get("/api/captures.csv", kViewToken);
    ASSERT_EQ(csv.result(), http::status::ok);
    EXPECT_EQ(std::count(csv.body().begin(), csv.body().end(), '\n'), 5);
    EXPECT_EQ(csv.body(), gportctl_csv(daemon_->socket(), dir_.file("captures.csv")));
    EXPECT_TRUE(csv.body().starts_with("index,utc,kind,imu_roll,")) << csv.body();
    EXPECT_NE(csv.body().find(R"("photo",)"), std::string::npos) << csv.body();
    EXPECT_NE(csv.body().find(R"("47.397742","-8.545594","488.2")"), std::string::npos);
    EXPECT_NE(csv.body().find(R"(,"","8.5","")"), std::string::npos) << "a string is no lat";
    EXPECT_NE(csv.body().find(R"("1e-07","-180","-0.5")"), std::string::npos) << csv.body();

    const auto features = json::parse(get("/api/captures.geojson").body()).at("features");
    ASSERT_EQ(features.size(), 2U) << "a numeric lat and lon make a point";
    EXPECT_EQ(features[1].at("geometry").at("coordinates"), json({-180, 1e-7, -0.5}));
}

}  // namespace
}  // namespace gport::testing
