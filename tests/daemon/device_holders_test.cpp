// device_holders() on a made-up /proc and lock directory (whose descriptor
// links point at /dev/null and /dev/zero), and on the real /proc with a
// pty this test holds.
#include "gport/daemon/device_holders.hpp"

#include <gtest/gtest.h>
#include <pty.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace gport::daemon {
namespace {

namespace fs = std::filesystem;

class FakeProc : public ::testing::Test {
  protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() / ("gport-holders-" + std::to_string(::getpid()));
        fs::remove_all(root_);
        fs::create_directories(places_.proc = (root_ / "proc").string());
        fs::create_directories(places_.locks = (root_ / "lock").string());
    }
    void TearDown() override { fs::remove_all(root_); }

    // Process `pid` named `name`, with descriptor `fd` linked to `target`.
    void process(pid_t pid, const std::string& name) const {
        fs::create_directories(proc(pid) + "/fd");
        std::ofstream(proc(pid) + "/comm") << name << "\n";
    }
    void descriptor(pid_t pid, int fd, const std::string& target) const {
        fs::create_symlink(target, proc(pid) + "/fd/" + std::to_string(fd));
    }
    std::string proc(pid_t pid) const { return places_.proc + "/" + std::to_string(pid); }
    std::string lock(const std::string& name) const { return places_.locks + "/LCK.." + name; }

    std::vector<DeviceHolders> holders(const std::vector<std::string>& devices,
                                       pid_t except = 0) const {
        return device_holders(devices, except, places_);
    }

    fs::path root_;
    HolderPlaces places_;
};

// A PID no process has: a child's, reaped.
pid_t dead_pid() {
    const pid_t child = ::fork();
    if (child == 0) {
        ::_exit(0);
    }
    ::waitpid(child, nullptr, 0);
    return child;
}

TEST_F(FakeProc, AProcessWithTheDeviceOpenHoldsItByTheDeviceNumber) {
    process(100, "autopilot");
    descriptor(100, 3, "/dev/null");
    process(101, "recorder");
    descriptor(101, 0, "/dev/zero");
    descriptor(101, 1, "socket:[4321]");
    const auto found = holders({"/dev/null", "/dev/zero", "/dev/full"});
    ASSERT_EQ(found.size(), 3U);
    ASSERT_EQ(found[0].holders.size(), 1U);
    EXPECT_EQ(found[0].holders[0].pid, 100);
    EXPECT_EQ(found[0].holders[0].name, "autopilot");
    EXPECT_EQ(found[0].holders[0].lock, "");
    ASSERT_EQ(found[1].holders.size(), 1U);
    EXPECT_EQ(found[1].holders[0].name, "recorder");
    EXPECT_TRUE(found[2].holders.empty());
    EXPECT_EQ(found[0].unchecked, 0U);
}

TEST_F(FakeProc, TwoDescriptorsOfOneProcessMakeOneHolderAndTheCallerIsLeftOut) {
    process(100, "twice");
    descriptor(100, 3, "/dev/null");
    descriptor(100, 4, "/dev/null");
    process(200, "caller");
    descriptor(200, 5, "/dev/null");
    const auto found = holders({"/dev/null"}, 200);
    ASSERT_EQ(found[0].holders.size(), 1U);
    EXPECT_EQ(found[0].holders[0].pid, 100);
}

TEST_F(FakeProc, ANameOutsideDevIsNotFollowed) {
    const auto alias = (root_ / "null-alias").string();
    fs::create_symlink("/dev/null", alias);
    process(100, "elsewhere");
    descriptor(100, 3, alias);  // the same device, by a path stat() could hang on
    EXPECT_TRUE(holders({"/dev/null"})[0].holders.empty());
}

TEST_F(FakeProc, UnreadableDescriptorsAreCountedAndAnExitedProcessIsNot) {
    fs::create_directories(proc(300));
    std::ofstream(proc(300) + "/fd") << "not a directory\n";  // as unreadable as another user's
    fs::create_directories(proc(301));                        // exited: no fd any more
    fs::create_directories(places_.proc + "/self");           // not a PID
    const auto found = holders({"/dev/null", "/dev/zero"});
    EXPECT_EQ(found[0].unchecked, 1U);
    EXPECT_EQ(found[1].unchecked, 1U);
}

TEST_F(FakeProc, ALockFileWithALivePidInAsciiOrBinaryHoldsTheDevice) {
    process(::getpid(), "minicom");
    std::ofstream(lock("null")) << "      " << ::getpid() << "\n";
    const std::int32_t pid = ::getpid();
    std::ofstream(lock("zero"), std::ios::binary)
        .write(reinterpret_cast<const char*>(&pid), sizeof pid);
    const auto found = holders({"/dev/null", "/dev/zero"});
    ASSERT_EQ(found[0].holders.size(), 1U);
    EXPECT_EQ(found[0].holders[0].pid, ::getpid());
    EXPECT_EQ(found[0].holders[0].name, "minicom");
    EXPECT_EQ(found[0].holders[0].lock, lock("null"));
    ASSERT_EQ(found[1].holders.size(), 1U);
    EXPECT_EQ(found[1].holders[0].lock, lock("zero"));
}

TEST_F(FakeProc, ALockUnderTheNameGivenOrTheNameItResolvesToCounts) {
    const auto link = (root_ / "gimbal").string();
    fs::create_symlink("/dev/null", link);
    std::ofstream(lock("gimbal")) << ::getpid() << "\n";
    const auto found = holders({link});
    ASSERT_EQ(found[0].holders.size(), 1U);
    EXPECT_EQ(found[0].holders[0].name, "?") << "no comm in the fake /proc";
    fs::remove(lock("gimbal"));
    std::ofstream(lock("null")) << ::getpid() << "\n";
    EXPECT_EQ(holders({link})[0].holders.size(), 1U);
}

TEST_F(FakeProc, AStaleOrUnreadableLockIsNoHolderAndIsLeftInPlace) {
    std::ofstream(lock("null")) << "      " << dead_pid() << "\n";
    std::ofstream(lock("zero")) << "not a pid\n";
    std::ofstream(lock("full")) << "-1\n";
    const auto found = holders({"/dev/null", "/dev/zero", "/dev/full"});
    for (const auto& f : found) {
        EXPECT_TRUE(f.holders.empty());
    }
    EXPECT_TRUE(fs::exists(lock("null"))) << "a stale lock is ignored, never removed";
}

// The attacker: /run/lock is writable by every user, and the probe runs as
// root. A FIFO named as a lock would block its read forever, a link could
// make root open any file (/dev/watchdog, which an open arms): neither is
// opened through, and neither is a lock, even one naming a live PID.
TEST_F(FakeProc, AFifoOrALinkPlantedAsALockIsNeitherOpenedThroughNorALock) {
    ASSERT_EQ(::mkfifo(lock("null").c_str(), 0600), 0);
    const auto target = (root_ / "pid").string();
    std::ofstream(target) << ::getpid() << "\n";
    fs::create_symlink(target, lock("zero"));
    const auto found = holders({"/dev/null", "/dev/zero"});  // returns: the FIFO is not waited on
    EXPECT_TRUE(found[0].holders.empty());
    EXPECT_TRUE(found[1].holders.empty()) << "a link to a file naming a live PID is no lock";
}

TEST_F(FakeProc, NoDeviceNoHolders) {
    std::ofstream(root_ / "plain") << "text\n";
    std::ofstream(lock("plain")) << ::getpid() << "\n";
    const auto found = holders({(root_ / "plain").string(), (root_ / "none").string()});
    EXPECT_TRUE(found[0].holders.empty());
    EXPECT_TRUE(found[1].holders.empty());
}

TEST(DeviceHolders, TheRealProcShowsAPtyThisProcessHolds) {
    int master = -1;
    int slave = -1;
    ASSERT_EQ(::openpty(&master, &slave, nullptr, nullptr, nullptr), 0);
    const std::string path = ::ptsname(master);
    const auto found = device_holders({path}, 0);
    ASSERT_EQ(found[0].holders.size(), 1U);
    EXPECT_EQ(found[0].holders[0].pid, ::getpid());
    EXPECT_TRUE(device_holders({path}, ::getpid())[0].holders.empty());
    ::close(slave);
    EXPECT_TRUE(device_holders({path}, 0)[0].holders.empty()) << "the master is another device";
    ::close(master);
}

TEST(DeviceHolders, Described) {
    EXPECT_EQ(describe_holders({{812, "mavproxy", ""}, {990, "minicom", "/run/lock/LCK..ttyUSB0"}}),
              "PID 812 mavproxy, PID 990 minicom (lock file /run/lock/LCK..ttyUSB0)");
    EXPECT_EQ(
        describe_holders({{1, "a", ""}, {2, "b", ""}, {3, "c", ""}, {4, "d", ""}, {5, "e", ""}}),
        "PID 1 a, PID 2 b, PID 3 c and 2 more");
}

}  // namespace
}  // namespace gport::daemon
