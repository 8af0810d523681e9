// gportd's journal entries name the client whose request caused them: the
// journal sink (injected send function) on the process's log context, as
// app/ wires it, and ipc's Dispatcher handling requests of a fake core.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/logger.h>

#include <memory>
#include <string>
#include <vector>

#include "fake_api.hpp"
#include "gport/base/log_context.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "gport/systemd/journal_sink.hpp"

namespace gport::testing {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::Not;

using Entry = std::vector<std::string>;

// Logs the core's motion events, as the core does, while they are emitted.
class LoggingObserver final : public daemon::CoreObserver {
  public:
    explicit LoggingObserver(const std::shared_ptr<spdlog::logger>& log) : log_(log) {}
    void on_attitude(const daemon::AttitudeSample&) override {}
    void on_link(const daemon::LinkEvent&) override {}
    void on_motion(const daemon::MotionEvent&) override { log_->info("motion started"); }

  private:
    const std::shared_ptr<spdlog::logger>& log_;
};

class ClientFieldsTest : public ::testing::Test {
  protected:
    ClientFieldsTest() {
        // As app/ does: the sink reads the process's context (not owned).
        std::shared_ptr<const base::LogContext> context(std::shared_ptr<void>(),
                                                        &base::process_log_context());
        auto sink =
            std::make_shared<systemd::JournalSink>("gportd", context, [this](const Entry& fields) {
                entries.push_back(fields);
                return 0;
            });
        log = std::make_shared<spdlog::logger>("test", sink);
        api.emit_motion = true;
        api.set_observer(&observer);
    }

    void handle(const std::string& line) {
        dispatcher.handle_line(line, client, [this](std::string reply) {
            log->info("reply {}", reply.substr(0, reply.size() - 1));
        });
    }

    static auto names_client() {
        return AllOf(Contains("GPORT_CLIENT_PID=4242"), Contains("GPORT_CLIENT_UID=1000"),
                     Contains("GPORT_CLIENT_ID=7"));
    }

    std::vector<Entry> entries;
    std::shared_ptr<spdlog::logger> log;
    LoggingObserver observer{log};
    FakeApi api;
    ipc::ClientState client{{7, 4242, 1000, 1000, {}}, {}, 0, {}};
    ipc::Dispatcher dispatcher{api, [] { return ipc::ServerStats{}; }};
};

TEST_F(ClientFieldsTest, LinesLoggedWhileARequestIsHandledNameTheClient) {
    handle(R"({"jsonrpc":"2.0","id":1,"method":"speed","params":{"yaw":10,"duration_ms":500}})");
    ASSERT_EQ(entries.size(), 2u);  // the motion, then the reply
    EXPECT_THAT(entries[0], Contains("MESSAGE=motion started"));
    EXPECT_THAT(entries[0], names_client());
    EXPECT_THAT(entries[1], names_client());

    log->info("after the request");
    EXPECT_THAT(entries.back(), Not(Contains("GPORT_CLIENT_PID=4242")));
}

TEST_F(ClientFieldsTest, ASettingsReplyDeliveredLaterNamesTheClient) {
    handle(R"({"jsonrpc":"2.0","id":2,"method":"get_settings"})");
    handle(R"([{"jsonrpc":"2.0","id":3,"method":"get_settings"}])");
    ASSERT_TRUE(entries.empty()) << "answered before the core did";
    api.run_settings();  // the core answers from the loop, outside any request
    ASSERT_EQ(entries.size(), 2u);
    EXPECT_THAT(entries[0], names_client());
    EXPECT_THAT(entries[1], names_client());

    log->info("after the replies");
    EXPECT_THAT(entries.back(), Not(Contains("GPORT_CLIENT_ID=7")));
}

}  // namespace
}  // namespace gport::testing
