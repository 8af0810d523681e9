// What the core logs for people reading the journal: no "stale" at every
// start, "link up" at info, settings changes with their old and new values,
// and the open error of a missing device in status.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <spdlog/sinks/ostream_sink.h>

#include <sstream>

#include "core_fixture.hpp"

namespace gport::testing {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

class LogWording : public CoreFixture {
  protected:
    void SetUp() override {
        auto sink = std::make_shared<spdlog::sinks::ostream_sink_st>(log_);
        sink->set_pattern("[%l] %v");
        logger = std::make_shared<spdlog::logger>("test", sink);
        logger->set_level(spdlog::level::debug);
    }

    std::ostringstream log_;
};

TEST_F(LogWording, StartWaitsForTheFirstAttitudeAtDebugThenLinkUpAtInfo) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    EXPECT_THAT(log_.str(), HasSubstr("[debug] device open, waiting for the first attitude\n"));
    EXPECT_THAT(log_.str(), HasSubstr("[info] link up: attitude arriving\n"));
    EXPECT_THAT(log_.str(), Not(HasSubstr("link stale")));
}

TEST_F(LogWording, SettingsChangesAreLoggedWithOldAndNewValues) {
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    const auto before = simulator->model().state().settings;
    std::optional<daemon::Outcome<daemon::Settings>> got;
    daemon::SettingsChange change;
    change.dead_zone = static_cast<std::uint8_t>(before.dead_zone + 1);
    core->set_settings(alice, change, [&](daemon::Outcome<daemon::Settings> r) { got = r; });
    ASSERT_TRUE(run_until([&] { return got.has_value(); }));
    ASSERT_TRUE(got->ok()) << got->error().message;
    EXPECT_THAT(log_.str(),
                HasSubstr(fmt::format("[info] settings changed by client {}: "
                                      "dead_zone {} -> {}\n",
                                      alice.id, before.dead_zone, before.dead_zone + 1)));
}

TEST_F(LogWording, StatusNamesWhyAMissingDeviceIsClosed) {
    core = std::make_unique<daemon::Core>(io, test_config("/nonexistent/gimbal"), logger);
    core->start();
    ASSERT_TRUE(run_until([&] { return core->status().counters.device_failures > 0; }));
    const auto status = core->status();
    EXPECT_FALSE(status.device_open);
    EXPECT_EQ(status.device_error, "No such file or directory");
}

}  // namespace
}  // namespace gport::testing
