// The "captures" section and --state-dir: where the capture log goes and how
// it rotates.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "gport/config/command_line.hpp"
#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

TEST(ConfigCaptures, DefaultsAreNoDirectoryOneMebibyteAndFourFiles) {
    auto c = load("{}");
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->captures.dir, "");
    EXPECT_EQ(c->captures.max_file_bytes, 1048576u);
    EXPECT_EQ(c->captures.keep_files, 4);
}

TEST(ConfigCaptures, ValuesAreRead) {
    auto c =
        load(R"({"captures": {"dir": "/data/gportd", "max_file_bytes": 65536, "keep_files": 10}})");
    ASSERT_TRUE(c.ok()) << c.error().text();
    EXPECT_EQ(c->captures.dir, "/data/gportd");
    EXPECT_EQ(c->captures.max_file_bytes, 65536u);
    EXPECT_EQ(c->captures.keep_files, 10);
}

TEST(ConfigCaptures, ErrorsNameTheKeyAndTheRange) {
    EXPECT_THAT(errors_of(R"({"captures": {"dir": "state"}})"),
                ElementsAre(ErrorWith("captures.dir", "absolute path", "/var/lib/gportd")));
    EXPECT_THAT(errors_of(R"({"captures": {"max_file_bytes": 100}})"),
                ElementsAre(ErrorWith("captures.max_file_bytes", "4096", "1073741824", "got 100")));
    EXPECT_THAT(errors_of(R"({"captures": {"keep_files": 1}})"),
                ElementsAre(ErrorWith("captures.keep_files", "2", "100", "got 1")));
    EXPECT_THAT(errors_of(R"({"captures": {"path": "/x"}})"),
                ElementsAre(ErrorWith("captures.path", "dir", "keep_files")));
}

TEST(ConfigCaptures, StateDirOnTheCommandLineIsCheckedAndWins) {
    const char* args[] = {"gportd", "--state-dir", "relative"};
    auto line = parse_command_line(args);
    ASSERT_FALSE(line.ok());
    EXPECT_THAT(line.error().messages.front(), HasSubstr("--state-dir"));
    const char* good[] = {"gportd", "--state-dir", "/srv/captures"};
    line = parse_command_line(good);
    ASSERT_TRUE(line.ok());
    EXPECT_EQ(line->state_dir, "/srv/captures");
}

}  // namespace
}  // namespace gport::config::test
