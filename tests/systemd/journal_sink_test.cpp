// The journal sink's entries, through an injected send function.
#include "gport/systemd/journal_sink.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gport/base/log_context.hpp"
#include "test_fds.hpp"

namespace gport::systemd {
namespace {

using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

using base::kFieldClientPid;
using base::kFieldClientUid;
using base::kFieldDevice;
using base::kFieldLink;
using base::LogContext;
using base::LogFields;

using Entry = std::vector<std::string>;

class JournalSinkTest : public ::testing::Test {
  protected:
    std::shared_ptr<spdlog::logger> make(JournalSendFn send) {
        auto sink = std::make_shared<JournalSink>("gportd", context, std::move(send));
        auto logger = std::make_shared<spdlog::logger>("test", sink);
        logger->set_level(spdlog::level::trace);
        return logger;
    }
    std::shared_ptr<spdlog::logger> make() {
        return make([this](const Entry& fields) {
            entries.push_back(fields);
            return 0;
        });
    }

    std::shared_ptr<LogContext> context = std::make_shared<LogContext>();
    std::vector<Entry> entries;
};

TEST_F(JournalSinkTest, SendsMessagePriorityAndIdentifier) {
    make()->info("gimbal answered in {} ms", 12);
    ASSERT_EQ(entries.size(), 1U);
    EXPECT_THAT(entries[0], ElementsAre("MESSAGE=gimbal answered in 12 ms", "PRIORITY=6",
                                        "SYSLOG_IDENTIFIER=gportd"));
}

TEST_F(JournalSinkTest, MapsLevelsToSyslogPriorities) {
    auto logger = make();
    logger->trace("t");
    logger->debug("d");
    logger->info("i");
    logger->warn("w");
    logger->error("e");
    logger->critical("c");
    ASSERT_EQ(entries.size(), 6U);
    const char* expected[] = {"PRIORITY=7", "PRIORITY=7", "PRIORITY=6",
                              "PRIORITY=4", "PRIORITY=3", "PRIORITY=2"};
    for (std::size_t i = 0; i < entries.size(); ++i) {
        EXPECT_EQ(entries[i].at(1), expected[i]) << "entry " << i;
    }
}

TEST_F(JournalSinkTest, SendsTheCallSiteWhenKnown) {
    auto logger = make();
    SPDLOG_LOGGER_ERROR(logger, "open failed");
    ASSERT_EQ(entries.size(), 1U);
    EXPECT_THAT(entries[0], Contains(HasSubstr("journal_sink_test.cpp")));
    EXPECT_THAT(entries[0], Contains(HasSubstr("CODE_LINE=")));
    EXPECT_THAT(entries[0], Contains(HasSubstr("CODE_FUNC=")));
}

TEST_F(JournalSinkTest, KeepsMultiLineMessagesWhole) {
    make()->warn("first line\nsecond line");
    ASSERT_EQ(entries.size(), 1U);
    EXPECT_EQ(entries[0].at(0), "MESSAGE=first line\nsecond line");
}

TEST_F(JournalSinkTest, SendsPersistentFieldsUntilTheyChange) {
    auto logger = make();
    context->set(kFieldDevice, "/dev/gimbal");
    context->set(kFieldLink, "up");
    logger->info("first");
    context->set(kFieldLink, "down");
    logger->warn("second");
    context->erase(kFieldDevice);
    logger->info("third");

    ASSERT_EQ(entries.size(), 3U);
    EXPECT_THAT(entries[0], Contains("GPORT_DEVICE=/dev/gimbal"));
    EXPECT_THAT(entries[0], Contains("GPORT_LINK=up"));
    EXPECT_THAT(entries[1], Contains("GPORT_LINK=down"));
    EXPECT_THAT(entries[1], Not(Contains("GPORT_LINK=up")));
    EXPECT_THAT(entries[2], Not(Contains(HasSubstr("GPORT_DEVICE="))));
    ASSERT_NE(context->find(kFieldLink), nullptr);
    EXPECT_EQ(*context->find(kFieldLink), "down");
}

TEST_F(JournalSinkTest, SendsScopedFieldsOnlyWithinTheirScope) {
    auto logger = make();
    context->set(kFieldLink, "up");
    {
        LogFields client(*context, {{kFieldClientPid, 4242}, {kFieldClientUid, 1000U}});
        logger->info("request");
        {
            LogFields nested(*context, {{kFieldClientPid, 7}, {kFieldLink, "stale"}});
            logger->info("nested");
        }
        logger->info("back");
    }
    logger->info("after");

    ASSERT_EQ(entries.size(), 4U);
    EXPECT_THAT(entries[0], Contains("GPORT_CLIENT_PID=4242"));
    EXPECT_THAT(entries[0], Contains("GPORT_CLIENT_UID=1000"));
    // The innermost scope wins, also over a persistent field.
    EXPECT_THAT(entries[1], Contains("GPORT_CLIENT_PID=7"));
    EXPECT_THAT(entries[1], Not(Contains("GPORT_CLIENT_PID=4242")));
    EXPECT_THAT(entries[1], Contains("GPORT_LINK=stale"));
    EXPECT_THAT(entries[1], Not(Contains("GPORT_LINK=up")));
    EXPECT_THAT(entries[2], Contains("GPORT_CLIENT_PID=4242"));
    EXPECT_THAT(entries[2], Contains("GPORT_LINK=up"));
    EXPECT_THAT(entries[3], Not(Contains(HasSubstr("GPORT_CLIENT_"))));
}

TEST_F(JournalSinkTest, RefusesInvalidFieldNames) {
    for (const char* name :
         {"", "gport_link", "_PID", "1ST", "GPORT-LINK", "MESSAGE", "PRIORITY", "CODE_FILE"}) {
        EXPECT_THROW(context->set(name, "x"), std::invalid_argument) << "'" << name << "'";
    }
    EXPECT_THROW(context->set(std::string(65, 'A'), "x"), std::invalid_argument);
    EXPECT_NO_THROW(context->set(std::string(64, 'A'), "x"));
    EXPECT_THROW(LogFields(*context, {{"bad name", 1}}), std::invalid_argument);
    try {
        context->set("gport_link", "up");
    } catch (const std::invalid_argument& error) {
        EXPECT_THAT(error.what(), HasSubstr("'gport_link'"));
        EXPECT_THAT(error.what(), HasSubstr("A-Z, 0-9 and '_'"));
    }
}

TEST_F(JournalSinkTest, FallsBackToStderrWhenTheJournalIsGone) {
    test::TempFile captured;
    {
        test::FdOverride stderr_to_file(STDERR_FILENO, captured.fd);
        make([](const Entry&) { return -ECONNREFUSED; })->error("device vanished");
    }
    EXPECT_EQ(captured.contents(), "<3>device vanished\n");
}

TEST(JournalPriority, FollowsSyslogLevels) {
    EXPECT_EQ(journal_priority(spdlog::level::debug), 7);
    EXPECT_EQ(journal_priority(spdlog::level::info), 6);
    EXPECT_EQ(journal_priority(spdlog::level::warn), 4);
    EXPECT_EQ(journal_priority(spdlog::level::err), 3);
    EXPECT_EQ(journal_priority(spdlog::level::critical), 2);
}

}  // namespace
}  // namespace gport::systemd
