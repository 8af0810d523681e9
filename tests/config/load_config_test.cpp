// load_config(): which file is read, and how the command line overrides it.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

using ::testing::ElementsAre;
using namespace std::chrono_literals;

class LoadConfig : public ::testing::Test {
  protected:
    void SetUp() override {
        std::string pattern = (std::filesystem::temp_directory_path() / "gport-config-XXXXXX");
        ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
        dir_ = pattern;
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text) {
        const auto path = dir_ / name;
        std::ofstream(path, std::ios::binary) << text;
        return path.string();
    }
    std::string missing() const { return (dir_ / "absent.json").string(); }

    std::filesystem::path dir_;
};

TEST_F(LoadConfig, MissingDefaultFileMeansBuiltInDefaults) {
    auto result = load_config(CommandLine{}, missing());
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_EQ(result->serial.device, Config{}.serial.device);
    EXPECT_EQ(result->keepalive.max_duration, 60000ms);
}

TEST_F(LoadConfig, ExplicitMissingFileIsAnError) {
    CommandLine command_line;
    command_line.config_path = missing();
    auto result = load_config(command_line, missing());
    EXPECT_THAT(result.error().messages,
                ElementsAre(ErrorWith(missing(), "cannot read the config file",
                                      "No such file or directory")));
}

TEST_F(LoadConfig, DefaultFileIsReadWhenPresent) {
    const auto path = write("gportd.json", R"({"serial": {"baud": 9600}})");
    auto result = load_config(CommandLine{}, path);
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_EQ(result->serial.baud, 9600u);
}

TEST_F(LoadConfig, ExplicitFileIsReadInsteadOfTheDefault) {
    const auto default_path = write("default.json", R"({"serial": {"baud": 9600}})");
    CommandLine command_line;
    command_line.config_path = write("mine.json", R"({"serial": {"baud": 19200}})");
    auto result = load_config(command_line, default_path);
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_EQ(result->serial.baud, 19200u);
}

TEST_F(LoadConfig, ErrorsInTheDefaultFileNameIt) {
    const auto path = write("gportd.json", R"({"log": {"level": "loud"}})");
    auto result = load_config(CommandLine{}, path);
    EXPECT_THAT(result.error().messages, ElementsAre(ErrorWith(path + ": log.level")));
}

TEST_F(LoadConfig, CommandLineOverridesTheFile) {
    const auto path = write("gportd.json", R"({
        "serial": {"device": "/dev/from-file", "baud": 9600},
        "socket": {"path": "/run/from-file.sock"},
        "log": {"level": "error"}})");
    auto command_line = parse_command_line(std::vector<const char*>{
        "gportd", "--config", path.c_str(), "--device=/dev/from-cli", "--socket",
        "/run/from-cli.sock", "--log-level", "trace", "--simulate"});
    ASSERT_TRUE(command_line.ok()) << command_line.error().text();
    auto result = load_config(*command_line, missing());
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_EQ(result->serial.device, "/dev/from-cli");
    EXPECT_EQ(result->socket.path, "/run/from-cli.sock");
    EXPECT_EQ(result->log.level, "trace");
    EXPECT_TRUE(result->simulate);
    EXPECT_EQ(result->serial.baud, 9600u);  // not overridden: from the file
}

TEST_F(LoadConfig, OverridesApplyOnTopOfBuiltInDefaults) {
    CommandLine command_line;
    command_line.device = "/dev/ttyACM0";
    auto result = load_config(command_line, missing());
    ASSERT_TRUE(result.ok()) << result.error().text();
    EXPECT_EQ(result->serial.device, "/dev/ttyACM0");
    EXPECT_EQ(result->socket.path, Config{}.socket.path);
}

TEST_F(LoadConfig, OverridesBuiltByCodeAreStillChecked) {
    CommandLine command_line;
    command_line.log_level = "chatty";
    command_line.device = "relative";
    auto result = load_config(command_line, missing());
    EXPECT_THAT(result.error().messages,
                ElementsAre(ErrorWith("--device: must be an absolute path"),
                            ErrorWith("--log-level: must be one of")));
}

TEST_F(LoadConfig, ADirectoryIsNotAConfigFile) {
    CommandLine command_line;
    command_line.config_path = dir_.string();
    EXPECT_THAT(load_config(command_line, missing()).error().messages,
                ElementsAre(ErrorWith(dir_.string(), "cannot read the config file",
                                      "it is a directory; a regular file is needed")));
}

// Opening a FIFO for reading waits for a writer: start-up must not hang on it.
TEST_F(LoadConfig, AFifoIsRefusedWithoutWaitingForAWriter) {
    const auto path = (dir_ / "fifo.json").string();
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    CommandLine command_line;
    command_line.config_path = path;
    EXPECT_THAT(load_config(command_line, missing()).error().messages,
                ElementsAre(ErrorWith(path, "it is a FIFO; a regular file is needed")));
    EXPECT_THAT(load_config_file(path).error().messages,
                ElementsAre(ErrorWith(path, "it is a FIFO; a regular file is needed")));
}

TEST_F(LoadConfig, ADeviceIsNotAConfigFile) {
    EXPECT_THAT(load_config_file("/dev/zero").error().messages,
                ElementsAre(ErrorWith("/dev/zero", "it is a character device")));
}

TEST_F(LoadConfig, AnOversizedFileIsRefused) {
    const auto path = write("huge.json", std::string(kMaxConfigBytes + 1, ' '));
    EXPECT_THAT(load_config_file(path).error().messages,
                ElementsAre(ErrorWith(path, "larger than 1048576 bytes")));
}

TEST_F(LoadConfig, AFileOfExactlyTheLimitIsRead) {
    std::string text = "{}";
    text.resize(kMaxConfigBytes, ' ');
    auto result = load_config_file(write("big.json", text));
    EXPECT_TRUE(result.ok()) << result.error().text();
}

TEST_F(LoadConfig, AnUnreadableDefaultFileIsAnErrorNotDefaults) {
    if (::geteuid() == 0) {
        GTEST_SKIP() << "root reads files regardless of their mode";
    }
    const auto path = write("gportd.json", "{}");
    ASSERT_EQ(::chmod(path.c_str(), 0), 0);
    EXPECT_THAT(load_config(CommandLine{}, path).error().messages,
                ElementsAre(ErrorWith(path, "Permission denied")));
}

}  // namespace
}  // namespace gport::config::test
