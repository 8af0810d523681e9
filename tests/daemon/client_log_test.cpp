// The core's lines about a motion carry its owner's journal fields
// (GPORT_CLIENT_PID, _UID, _ID), even when nothing of the client is on the
// stack: a motion that ends on its own timer.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/details/null_mutex.h>
#include <spdlog/sinks/base_sink.h>

#include <memory>
#include <string>
#include <vector>

#include "core_fixture.hpp"
#include "gport/base/log_context.hpp"

namespace gport::testing {
namespace {

using ::testing::Contains;
using ::testing::IsEmpty;
using ::testing::Not;

struct Line {
    std::string message;
    std::vector<std::string> fields;  // "NAME=value", as the journal sink sends them
};

// Records each line with the fields of the process's log context at the time.
class FieldsSink final : public spdlog::sinks::base_sink<spdlog::details::null_mutex> {
  public:
    explicit FieldsSink(std::vector<Line>& lines) : lines_(lines) {}

  protected:
    void sink_it_(const spdlog::details::log_msg& msg) override {
        Line line{std::string(msg.payload.data(), msg.payload.size()), {}};
        base::process_log_context().append_to(line.fields);
        lines_.push_back(std::move(line));
    }
    void flush_() override {}

  private:
    std::vector<Line>& lines_;
};

const Line* find_line(const std::vector<Line>& lines, const std::string& start) {
    for (const auto& line : lines) {
        if (line.message.rfind(start, 0) == 0) {
            return &line;
        }
    }
    return nullptr;
}

class ClientLogTest : public CoreFixture {
  protected:
    std::vector<Line> lines;  // alive until the core is shut down in TearDown
};

TEST_F(ClientLogTest, MotionLinesCarryTheOwnersJournalFields) {
    logger = std::make_shared<spdlog::logger>("test", std::make_shared<FieldsSink>(lines));
    logger->set_level(spdlog::level::info);
    start();
    ASSERT_TRUE(run_until([&] { return link_up(); }));
    ASSERT_TRUE(core->speed(alice, {0, 0, 500}, 100ms).ok());
    ASSERT_TRUE(run_until([&] { return find_line(lines, "motion ended") != nullptr; }));

    const auto* started = find_line(lines, "motion started");
    ASSERT_NE(started, nullptr);
    EXPECT_THAT(started->fields, Contains("GPORT_CLIENT_PID=1001"));
    // Ended by its own timer: no request of alice's is being handled.
    const auto* ended = find_line(lines, "motion ended (duration)");
    ASSERT_NE(ended, nullptr);
    EXPECT_THAT(ended->fields, Contains("GPORT_CLIENT_PID=1001"));
    EXPECT_THAT(ended->fields, Contains("GPORT_CLIENT_UID=1001"));
    EXPECT_THAT(ended->fields, Contains("GPORT_CLIENT_ID=1"));
    // Other lines name no client.
    const auto* link = find_line(lines, "link up");
    ASSERT_NE(link, nullptr);
    EXPECT_THAT(link->fields, Not(Contains("GPORT_CLIENT_PID=1001")));
    std::vector<std::string> now;
    base::process_log_context().append_to(now);
    EXPECT_THAT(now, IsEmpty()) << "a scope outlived its line";
}

}  // namespace
}  // namespace gport::testing
