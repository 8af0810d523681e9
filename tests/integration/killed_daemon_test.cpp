// gportd killed with SIGKILL leaves its TIOCEXCL on gport-sim's pty, which
// outlives it there (the simulator keeps the master open); a new gportd on
// the same link must still bring the link up, as after a real adapter's
// last close. gport-sim clears the mode when it may (CAP_SYS_ADMIN), and
// otherwise moves the link to a fresh pty: both ways are driven here.
#include <gtest/gtest.h>
#include <signal.h>

#include <fstream>

#include "emulation.hpp"
#include "harness.hpp"

namespace gport::testing {
namespace {

// Whether this process may open a tty another has made exclusive
// (CAP_SYS_ADMIN, bit 21 of the effective capabilities).
bool has_cap_sys_admin() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("CapEff:", 0) == 0) {
            return ((std::stoull(line.substr(7), nullptr, 16) >> 21) & 1U) != 0;
        }
    }
    return false;
}

bool traced_event(SimProcess& sim, const std::string& event) {
    const std::string needle = "\"event\":\"" + event + "\"";
    return sim.process()
        .wait_line([&](const std::string& l) { return l.find(needle) != std::string::npos; })
        .has_value();
}

// Runs a program without CAP_SYS_ADMIN, as an unprivileged user would: it
// may not open a tty another process left exclusive. Empty when we lack the
// capability anyway.
std::vector<std::string> without_cap_sys_admin() {
    if (!has_cap_sys_admin()) {
        return {};
    }
    return {"/usr/bin/setpriv", "--bounding-set=-sys_admin", "--inh-caps=-sys_admin", "--"};
}

// gportd up on the sim's link, killed with SIGKILL; the sim reports `event`;
// a second gportd on the same link, without CAP_SYS_ADMIN as under systemd,
// gets the link up (without the sim's release it would get EBUSY forever).
void restart_after_kill(SimProcess& sim, const TempDir& dir, const std::string& event) {
    {
        DaemonProcess first(dir, {"--device", sim.link()});
        Client client(first.socket());
        ASSERT_TRUE(client.connected());
        ASSERT_TRUE(link_up(client));
        first.process().signal(SIGKILL);
        ASSERT_EQ(first.process().wait(), 128 + SIGKILL);
    }
    DaemonProcess second(dir, {"--device", sim.link()}, {}, "", without_cap_sys_admin());
    Client client(second.socket());
    ASSERT_TRUE(client.connected());
    EXPECT_TRUE(link_up(client));
    ASSERT_TRUE(traced_event(sim, event)) << "gport-sim did not report " << event;
}

TEST(KilledDaemon, ASimThatMayClearTheExclusiveModeClearsIt) {
    if (!has_cap_sys_admin()) {
        GTEST_SKIP() << "needs CAP_SYS_ADMIN (run as root); the other test covers the rest";
    }
    if (auto missing = tiocgexcl_missing()) {
        GTEST_SKIP() << *missing;
    }
    TempDir dir;
    SimProcess sim(dir);
    restart_after_kill(sim, dir, "exclusive_cleared");
}

TEST(KilledDaemon, AnUnprivilegedSimMovesTheLinkToAFreshPty) {
    TempDir dir;
    SimProcess sim(dir, {}, without_cap_sys_admin());
    restart_after_kill(sim, dir, "pty_replaced");
}

}  // namespace
}  // namespace gport::testing
