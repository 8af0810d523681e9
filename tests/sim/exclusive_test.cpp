// A client's exclusive mode (TIOCEXCL) must not outlive it: on a pty it
// would, because the slave's tty lives as long as the simulator's master, so
// the simulator releases it when the client goes (docs/simulator.md).
#include <gtest/gtest.h>
#include <sys/ioctl.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "emulation.hpp"
#include "gport/sim/pty.hpp"
#include "pty_helpers.hpp"

namespace gport::sim {
namespace {

using namespace gport::sim::testing;

// Opening an exclusive tty is refused (EBUSY) unless the opener has
// CAP_SYS_ADMIN (bit 21 of the effective set).
bool may_open_exclusive_ttys() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("CapEff:", 0) == 0) {
            return ((std::stoull(line.substr(7), nullptr, 16) >> 21) & 1U) != 0;
        }
    }
    return false;
}

// Under an emulator without TIOCGEXCL (qemu-user) the simulator cannot see
// the mode, and says so on every client's departure.
#define GPORT_SKIP_WITHOUT_TIOCGEXCL()                            \
    do {                                                          \
        if (auto missing = gport::testing::tiocgexcl_missing()) { \
            GTEST_SKIP() << *missing;                             \
        }                                                         \
    } while (false)

// The simulator streams to this client: an attitude frame arrives (within
// eventually()'s patience, not a fixed window: a loaded machine's simulator
// may notice the client late).
bool streams_attitude(Client& client) {
    return eventually([&] { return !decode_all(client.read_for(100ms)).attitudes().empty(); });
}

bool exclusive(int fd) {
    int value = 0;
    EXPECT_EQ(::ioctl(fd, TIOCGEXCL, &value), 0);
    return value != 0;
}

TEST(ReleaseExclusive, AFreshSlaveIsNotExclusive) {
    GPORT_SKIP_WITHOUT_TIOCGEXCL();
    const PtyMaster pty = open_pty();
    EXPECT_EQ(release_exclusive(pty.slave_path), Exclusivity::kNone);
    ::close(pty.fd);
}

TEST(ReleaseExclusive, TheModeOutlivesItsClientUntilReleased) {
    GPORT_SKIP_WITHOUT_TIOCGEXCL();
    const PtyMaster pty = open_pty();
    {
        Client client(pty.slave_path);
        ASSERT_TRUE(client.ok());
        ASSERT_EQ(::ioctl(client.fd(), TIOCEXCL), 0);
    }
    if (may_open_exclusive_ttys()) {
        EXPECT_EQ(release_exclusive(pty.slave_path), Exclusivity::kCleared);
        EXPECT_EQ(release_exclusive(pty.slave_path), Exclusivity::kNone);
    } else {
        EXPECT_EQ(release_exclusive(pty.slave_path), Exclusivity::kStuck);
    }
    ::close(pty.fd);
}

TEST(ReleaseExclusive, AMissingSlaveIsAnErrorNamingIt) {
    try {
        release_exclusive("/dev/pts/no-such-slave");
        FAIL() << "expected std::system_error";
    } catch (const std::system_error& e) {
        EXPECT_NE(std::string(e.what()).find("/dev/pts/no-such-slave"), std::string::npos);
    }
}

TEST(PtySimulator, AGoneClientsExclusiveModeIsReleased) {
    GPORT_SKIP_WITHOUT_TIOCGEXCL();
    const auto link =
        (std::filesystem::temp_directory_path() / ("gport-sim-excl." + std::to_string(::getpid())))
            .string();
    SimOptions o;
    o.link_path = link;
    SimThread sim(o);
    {
        Client client(link);
        ASSERT_TRUE(client.ok());
        ASSERT_EQ(::ioctl(client.fd(), TIOCEXCL), 0);
        ASSERT_TRUE(eventually([&] { return sim.stats().peer_opens == 1; }));
    }
    // Privileged, the simulator clears the mode; otherwise it moves the link
    // to a fresh pty. Either way the next client opens the link and is free.
    ASSERT_TRUE(eventually([&] {
        return sim.traced("\"event\":\"exclusive_cleared\"") ||
               sim.traced("\"event\":\"pty_replaced\"");
    }));
    Client again(link);
    ASSERT_TRUE(again.ok());
    EXPECT_FALSE(exclusive(again.fd()));
    EXPECT_TRUE(streams_attitude(again));
}

// The systemd e2e once lost its link for a whole run this way: the daemon
// started by the package opened the device and was stopped before the
// simulator's next tick, leaving the mode behind unseen. Here the client
// comes and goes on the simulator's own thread, so no tick can see it.
TEST(PtySimulator, AnUnseenClientsExclusiveModeIsReleasedToo) {
    GPORT_SKIP_WITHOUT_TIOCGEXCL();
    const auto link = (std::filesystem::temp_directory_path() /
                       ("gport-sim-unseen." + std::to_string(::getpid())))
                          .string();
    SimOptions o;
    o.link_path = link;
    SimThread sim(o);
    const bool set = sim.on_io([&](PtySimulator&) {
        Client client(link);
        return client.ok() && ::ioctl(client.fd(), TIOCEXCL) == 0;
    });
    ASSERT_TRUE(set);
    ASSERT_TRUE(eventually([&] { return sim.traced("unseen_client_left_exclusive"); }));
    EXPECT_EQ(sim.stats().peer_opens, 0U);
    Client again(link);
    ASSERT_TRUE(again.ok());
    EXPECT_FALSE(exclusive(again.fd()));
    EXPECT_TRUE(streams_attitude(again));
}

TEST(PtySimulator, AClientThatNeverSetTheModeLeavesTheSameSlave) {
    GPORT_SKIP_WITHOUT_TIOCGEXCL();
    SimThread sim(SimOptions{});
    const std::string slave = sim.on_io([](PtySimulator& s) { return s.slave_path(); });
    {
        Client client(sim.path());
        ASSERT_TRUE(eventually([&] { return sim.stats().peer_opens == 1; }));
    }
    ASSERT_TRUE(eventually([&] { return sim.traced("\"event\":\"peer_closed\""); }));
    EXPECT_EQ(sim.on_io([](PtySimulator& s) { return s.slave_path(); }), slave);
    EXPECT_EQ(sim.stats().pty_replacements, 0U);
    EXPECT_FALSE(sim.traced("exclusive"));
}

}  // namespace
}  // namespace gport::sim
