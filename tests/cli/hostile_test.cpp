// gportctl against a hostile gportd (tests/client/hostile_server.hpp): when
// the client library ends the connection or gives up waiting, gportctl says
// why and exits 69, never hangs or aborts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include "gport/cli/run.hpp"
#include "hostile_server.hpp"

namespace gport::cli {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::HostilePeer;
using testing::HostileServer;

struct HostileRun {
    int status;
    std::string err;
};

HostileRun run(const HostileServer& server, std::vector<std::string> args) {
    args.insert(args.begin(), {"--socket", server.path()});
    std::ostringstream out;
    std::ostringstream err;
    const int status = main_with(args, nullptr, out, err, [] { return false; }, {});
    return {status, err.str()};
}

TEST(GportctlHostile, ALineThatIsNotJsonIsNamed) {
    HostileServer server([](HostilePeer& peer, const json&) { peer.send("{\"id\":1,]\n"); });
    const auto ran = run(server, {"status"});
    EXPECT_EQ(ran.status, kExitUnavailable);
    EXPECT_THAT(ran.err, HasSubstr("gportd sent a line that is not JSON"));
}

TEST(GportctlHostile, ADeepLineDuringAWatchEndsIt) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        peer.reply(request, {{"topics", {"link"}}});
        peer.send(std::string(1'000'000, '[') + std::string(1'000'000, ']') + "\n");
    });
    const auto ran = run(server, {"watch", "link"});
    EXPECT_EQ(ran.status, kExitUnavailable);
    EXPECT_THAT(ran.err, HasSubstr("nested deeper than 64 levels"));
}

// gportctl prints results by type (libgport-client's results.hpp): a result
// of the wrong shape is named, not printed with made-up values.
TEST(GportctlHostile, AResultOfTheWrongShapeIsNamed) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        peer.reply(request, {{"link", "up"}, {"uptime_ms", "a while"}});
    });
    const auto ran = run(server, {"status"});
    EXPECT_EQ(ran.status, kExitUnavailable);
    EXPECT_THAT(ran.err, HasSubstr("cannot read a status ("));
}

// Takes the library's default call timeout (10 s).
TEST(GportctlHostile, ASilentDaemonGivesUpAfterTheCallTimeout) {
    HostileServer server([](HostilePeer&, const json&) {});
    const auto ran = run(server, {"photo"});
    EXPECT_EQ(ran.status, kExitUnavailable);
    EXPECT_THAT(ran.err, HasSubstr("no reply to photo within 10000 ms"));
}

}  // namespace
}  // namespace gport::cli
