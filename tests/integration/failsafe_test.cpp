// Issue 12 item 3 end to end: the failsafe policies of the real gportd, seen
// in gport-sim's trace. A speed motion whose owner goes away ends with zero
// speed then a centre frame (on_owner_gone: center); SIGTERM during a motion
// sends zero speed then an angle frame holding the position (on_shutdown: hold).
#include <gtest/gtest.h>
#include <signal.h>

#include <memory>
#include <string>

#include "harness.hpp"

namespace gport::testing {
namespace {

bool is_control(const std::string& line, const std::string& mode) {
    auto j = Json::parse(line, nullptr, false);
    return j.is_object() && j.value("cmd", "") == "0x85" && j.value("mode", "") == mode;
}

TEST(FailsafeEndToEnd, OwnerGoneCenterSendsZeroSpeedThenCentre) {
    TempDir dir;
    SimProcess sim(dir);
    DaemonProcess daemon(dir, {"--device", sim.link()}, {},
                         R"("failsafe": {"on_owner_gone": "center"})");
    Client watcher(daemon.socket());
    ASSERT_TRUE(watcher.connected());
    ASSERT_TRUE(link_up(watcher));
    watcher.call("subscribe", {{"topics", {"motion"}}});
    {
        Client owner(daemon.socket());
        ASSERT_TRUE(owner.connected());
        auto reply = owner.call("speed", {{"pitch", 10}, {"duration_ms", 30000}});
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
        ASSERT_TRUE(sim.wait_speed({0, 1000, 0}));
    }  // the owner closes its connection
    EXPECT_TRUE(sim.wait_speed({0, 0, 0})) << "no zero speed after the owner left";
    EXPECT_TRUE(sim.process().wait_line([](const std::string& l) {
        return is_control(l, "center");
    })) << "no centre frame after the zero speed";
    bool owner_gone = false;
    while (auto n = watcher.notification("motion", 5s)) {
        if ((*n)["params"].value("reason", "") == "owner_gone") {
            owner_gone = true;
            break;
        }
    }
    EXPECT_TRUE(owner_gone) << "the motion must still end, reason owner_gone";
}

TEST(FailsafeEndToEnd, SigtermHoldSendsZeroSpeedThenAnAngleFrame) {
    TempDir dir;
    SimProcess sim(dir);
    DaemonProcess daemon(dir, {"--device", sim.link()}, {},
                         R"("failsafe": {"on_shutdown": "hold"})");
    Client client(daemon.socket());
    ASSERT_TRUE(client.connected());
    ASSERT_TRUE(link_up(client));
    auto reply = client.call("speed", {{"yaw", 20}, {"duration_ms", 30000}});
    ASSERT_TRUE(reply.contains("result")) << reply.dump();
    ASSERT_TRUE(sim.wait_speed({0, 0, 2000}));
    daemon.process().signal(SIGTERM);
    EXPECT_TRUE(sim.wait_speed({0, 0, 0})) << "no zero speed after SIGTERM";
    auto angle =
        sim.process().wait_line([](const std::string& l) { return is_control(l, "angle"); });
    EXPECT_TRUE(angle.has_value()) << "no angle frame after the zero speed";
    EXPECT_EQ(daemon.process().wait(), 0);
}

}  // namespace
}  // namespace gport::testing
