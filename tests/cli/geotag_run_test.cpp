// gportctl photo and record with a position and meta (issue 32): the
// options checked before any connection, the meta sent, the capture's
// index printed.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <mutex>
#include <sstream>

#include "gport/cli/run.hpp"
#include "hostile_server.hpp"

namespace gport::cli::geotag_run_test {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::HostilePeer;
using testing::HostileServer;

struct Ran {
    int status;
    std::string out;
    std::string err;
};

// A gportd whose photo and record make capture 12, recording each request;
// it serves one connection (one run).
class CameraDaemon {
  public:
    CameraDaemon()
        : server_([this](HostilePeer& peer, const json& request) {
              {
                  const std::lock_guard lock(mutex_);
                  requests_.push_back(request);
              }
              json capture = {{"index", 12}, {"kind", request["method"]}, {"utc_us", 1}};
              json result = {{"sent", true}, {"capture", capture}};
              if (request["method"] == "record") {
                  result["recording"] = "on";
              }
              peer.reply(request, result);
          }) {}

    Ran run(std::vector<std::string> args) {
        args.insert(args.begin(), {"--socket", server_.path()});
        std::ostringstream out;
        std::ostringstream err;
        const int status = main_with(args, nullptr, out, err, [] { return false; }, {});
        return {status, out.str(), err.str()};
    }

    std::vector<json> requests() {
        const std::lock_guard lock(mutex_);
        return requests_;
    }

  private:
    std::mutex mutex_;
    std::vector<json> requests_;
    HostileServer server_;
};

TEST(Geotag, OutOfRangeOrIncompletePositionsAreUsageErrorsNamingTheOption) {
    CameraDaemon daemon;
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"photo", "--lat", "91", "--lon", "8"}, "--lat"},
        {{"photo", "--lat", "-90.5", "--lon", "8"}, "-90 to 90"},
        {{"photo", "--lat", "47", "--lon", "180.1"}, "--lon"},
        {{"record", "on", "--lat", "47", "--lon", "-181"}, "-180 to 180"},
        {{"photo", "--lat", "north", "--lon", "8"}, "--lat"},
        {{"photo", "--lat", "47"}, "photo: --lat needs --lon"},
        {{"photo", "--lon", "8"}, "photo: --lon needs --lat"},
        {{"photo", "--alt", "400"}, "photo: --alt needs --lat and --lon"},
        {{"photo", "--meta", "[1]"}, "photo: --meta is a array: expected a JSON object"},
        {{"photo", "--meta", "{"}, "photo: --meta is not valid JSON"},
        {{"record", "--meta", "{\"lat\":1}", "--lat", "2", "--lon", "3"},
         "record: --meta has \"lat\" and --lat sets it too"},
        {{"photo", "--meta", "{\"alt_m\":1}", "--lat", "2", "--lon", "3", "--alt", "4"},
         "--meta has \"alt_m\" and --alt sets it too"},
        {{"photo", "--meta", std::string(40, '[') + std::string(40, ']')}, "deeper than 32"},
    };
    for (const auto& [args, expected] : cases) {
        const auto ran = daemon.run(args);
        EXPECT_EQ(ran.status, kExitUsage) << args[1];
        EXPECT_THAT(ran.err, HasSubstr(expected));
        EXPECT_THAT(ran.err, HasSubstr("Try 'gportctl " + args[0] + " --help'."));
    }
    EXPECT_TRUE(daemon.requests().empty());
}

TEST(Geotag, PhotoSendsThePositionAndMetaAndPrintsTheCapture) {
    CameraDaemon daemon;
    const auto ran = daemon.run({"photo", "--lat", "47.397742", "--lon", "-8.5", "--alt", "488.5",
                                 "--meta", R"({"flight":"F12"})"});
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_EQ(ran.out, "photo: sent, capture 12\n");
    ASSERT_EQ(daemon.requests().size(), 1u);
    EXPECT_EQ(daemon.requests()[0]["params"]["meta"],
              json({{"lat", 47.397742}, {"lon", -8.5}, {"alt_m", 488.5}, {"flight", "F12"}}));
}

TEST(Geotag, MetaAloneAndNothingAtAll) {
    CameraDaemon with_meta;
    EXPECT_EQ(with_meta.run({"photo", "--meta", R"({"n":1})"}).status, kExitOk);
    ASSERT_EQ(with_meta.requests().size(), 1u);
    EXPECT_EQ(with_meta.requests()[0]["params"]["meta"], json({{"n", 1}}));
    CameraDaemon plain;
    EXPECT_EQ(plain.run({"photo"}).out, "photo: sent, capture 12\n");
    ASSERT_EQ(plain.requests().size(), 1u);
    EXPECT_FALSE(plain.requests()[0].value("params", json::object()).contains("meta"));
}

TEST(Geotag, RecordToo) {
    CameraDaemon daemon;
    const auto ran = daemon.run({"record", "on", "--force", "--lat", "-90", "--lon", "180"});
    EXPECT_EQ(ran.status, kExitOk) << ran.err;
    EXPECT_EQ(ran.out, "record: sent, capture 12; recording on (assumed)\n");
    ASSERT_EQ(daemon.requests().size(), 1u);
    EXPECT_EQ(daemon.requests()[0]["params"],
              json({{"on", true}, {"force", true}, {"meta", {{"lat", -90.0}, {"lon", 180.0}}}}));
}

TEST(Geotag, JsonPrintsTheResult) {
    CameraDaemon daemon;
    const auto script = daemon.run({"--json", "photo", "--lat", "1", "--lon", "2"});
    ASSERT_EQ(script.status, kExitOk) << script.err;
    EXPECT_EQ(json::parse(script.out)["capture"]["index"], 12);
}

}  // namespace
}  // namespace gport::cli::geotag_run_test
