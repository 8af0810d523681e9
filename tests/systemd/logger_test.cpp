// stderr_is_journal() and make_logger()'s choice of target.
#include "gport/systemd/logger.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <sys/stat.h>
#include <unistd.h>

#include <memory>
#include <string>

#include "gport/systemd/journal_sink.hpp"
#include "test_fds.hpp"

namespace gport::systemd {
namespace {

using base::LogContext;
using test::EnvOverride;
using test::FdOverride;
using test::TempFile;
using ::testing::ContainsRegex;
using ::testing::HasSubstr;
using ::testing::Not;

// The JOURNAL_STREAM value systemd would set for `fd`.
std::string journal_stream_of(int fd) {
    struct stat st {};
    EXPECT_EQ(fstat(fd, &st), 0);
    return std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
}

TEST(IsJournalStream, MatchesDeviceAndInode) {
    TempFile file;
    TempFile other;
    EXPECT_TRUE(is_journal_stream(file.fd, journal_stream_of(file.fd)));
    EXPECT_FALSE(is_journal_stream(file.fd, journal_stream_of(other.fd)));
}

TEST(IsJournalStream, RejectsMalformedValues) {
    TempFile file;
    const std::string good = journal_stream_of(file.fd);
    for (const std::string& value : {std::string(), std::string(":"), std::string("12"), good + "x",
                                     "x" + good, good + ":1", std::string("-1:-1")}) {
        EXPECT_FALSE(is_journal_stream(file.fd, value)) << "'" << value << "'";
    }
    EXPECT_FALSE(is_journal_stream(-1, good));
}

TEST(StderrIsJournal, TrueOnlyWhenJournalStreamNamesStderr) {
    TempFile journal;
    FdOverride stderr_to_file(STDERR_FILENO, journal.fd);
    {
        EnvOverride env("JOURNAL_STREAM", journal_stream_of(journal.fd));
        EXPECT_TRUE(stderr_is_journal());
        EXPECT_EQ(resolve_target(LogTarget::automatic), LogTarget::journal);
        EXPECT_EQ(resolve_target(LogTarget::stderr_stream), LogTarget::stderr_stream);
    }
    {
        // Inherited from a unit, but stderr was redirected since.
        TempFile elsewhere;
        EnvOverride env("JOURNAL_STREAM", journal_stream_of(elsewhere.fd));
        EXPECT_FALSE(stderr_is_journal());
        EXPECT_EQ(resolve_target(LogTarget::automatic), LogTarget::stderr_stream);
    }
    {
        EnvOverride env("JOURNAL_STREAM", std::nullopt);
        EXPECT_FALSE(stderr_is_journal());
        EXPECT_EQ(resolve_target(LogTarget::journal), LogTarget::journal);
    }
}

TEST(MakeLogger, UsesTheJournalSinkWhenStderrIsTheJournal) {
    TempFile journal;
    FdOverride stderr_to_file(STDERR_FILENO, journal.fd);
    EnvOverride env("JOURNAL_STREAM", journal_stream_of(journal.fd));
    auto logger = make_logger({}, std::make_shared<LogContext>());
    ASSERT_EQ(logger->sinks().size(), 1U);
    EXPECT_NE(std::dynamic_pointer_cast<JournalSink>(logger->sinks()[0]), nullptr);
    EXPECT_EQ(logger->name(), "gportd");
}

TEST(MakeLogger, WritesReadableLinesToStderrOtherwise) {
    TempFile captured;
    {
        FdOverride stderr_to_file(STDERR_FILENO, captured.fd);
        EnvOverride env("JOURNAL_STREAM", std::nullopt);
        auto context = std::make_shared<LogContext>();
        auto logger =
            make_logger({.name = "gportd", .level = spdlog::level::warn}, std::move(context));
        EXPECT_EQ(std::dynamic_pointer_cast<JournalSink>(logger->sinks()[0]), nullptr);
        logger->info("not at this level");
        logger->warn("link stale");
        logger->flush();
    }
    const std::string text = captured.contents();
    EXPECT_THAT(text, Not(HasSubstr("not at this level")));
    EXPECT_THAT(text,
                ContainsRegex("^[0-9]{4}-[0-9]{2}-[0-9]{2} [0-9]{2}:[0-9]{2}:[0-9]{2}\\.[0-9]{3} "
                              "\\[warning\\] link stale\n$"));
    EXPECT_THAT(text, Not(HasSubstr("\x1b[")));  // no colour codes
}

}  // namespace
}  // namespace gport::systemd
