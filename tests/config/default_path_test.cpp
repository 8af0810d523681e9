// The default config file follows the prefix gportd was installed to, as
// GNUInstallDirs maps the configuration directory; outside an installed bin/
// (the build tree) it is the .deb's /etc/gportd/gportd.json.
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace gport::config::test {
namespace {

std::string path_for(const std::string& program, const std::string& forced = "") {
    return default_config_path_for(program, "bin", "etc", forced);
}

TEST(DefaultConfigPath, TheDebsUsrReadsEtc) {
    EXPECT_EQ(path_for("/usr/bin/gportd"), "/etc/gportd/gportd.json");
}

TEST(DefaultConfigPath, AnyOtherPrefixReadsItsOwnEtc) {
    EXPECT_EQ(path_for("/home/ann/gport/bin/gportd"), "/home/ann/gport/etc/gportd/gportd.json");
    EXPECT_EQ(path_for("/usr/local/bin/gportd"), "/usr/local/etc/gportd/gportd.json");
}

TEST(DefaultConfigPath, OptPrefixesReadEtcOpt) {
    EXPECT_EQ(path_for("/opt/gport/bin/gportd"), "/etc/opt/gport/gportd/gportd.json");
}

TEST(DefaultConfigPath, OutsideAnInstalledBinItIsTheFallback) {
    EXPECT_EQ(path_for("/work/build/app/gportd"), kFallbackConfigPath);
    EXPECT_EQ(path_for(""), kFallbackConfigPath);
    // A directory merely ending in "bin" is not bin/.
    EXPECT_EQ(path_for("/work/xbin/gportd"), kFallbackConfigPath);
}

TEST(DefaultConfigPath, LayoutsFromTheBuildAreHonoured) {
    EXPECT_EQ(default_config_path_for("/p/sbin/gportd", "sbin", "etc", ""),
              "/p/etc/gportd/gportd.json");
    EXPECT_EQ(default_config_path_for("/p/x/bin/gportd", "x/bin", "conf", ""),
              "/p/conf/gportd/gportd.json");
    EXPECT_EQ(default_config_path_for("/p/bin/gportd", "bin", "/srv/etc", ""),
              "/srv/etc/gportd/gportd.json");
}

TEST(DefaultConfigPath, AForcedDirectoryWins) {
    EXPECT_EQ(path_for("/usr/bin/gportd", "/srv/gportd"), "/srv/gportd/gportd.json");
}

TEST(DefaultConfigPath, TheBuildTreesGportdUsesTheFallback) {
    // This test program is not in an installed bin/ either.
    EXPECT_EQ(default_config_path(), kFallbackConfigPath);
}

}  // namespace
}  // namespace gport::config::test
