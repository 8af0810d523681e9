// The attitude channel's edges in a connection's life: a session that
// closes in the middle of a batch, replies held behind a waiting request,
// the waker thread that makes every wake, and shutdown.
#include <gtest/gtest.h>

#include <string>

#include "channel_helpers.hpp"

namespace gport::ipc {
namespace {

using nlohmann::json;
using testing::channel_result;
using testing::DescriptorClient;
using testing::open_channel;
using testing::publish_samples;
using testing::ServerHarness;

// A batch whose `speed` members each publish a motion event to a client
// that never reads: once its socket and its queue are full, the event
// overflows and the session closes synchronously, in the middle of the
// batch. The batch's attitude_channel member then runs for a client that
// is gone; it used to make a wake block for it that nothing ever freed
// (a memfd and a mapping per attempt, until EMFILE).
TEST(ChannelLifecycle, ASessionClosedInTheMiddleOfABatchGetsNoWakeBlock) {
    config::SocketConfig config;
    config.queue_limit = 4;
    ServerHarness h(config);
    h.on_io([&] { h.api.emit_motion = true; });
    DescriptorClient reader(h.path());  // keeps the channel open meanwhile
    open_channel(reader);
    DescriptorClient victim(h.path());
    ASSERT_EQ(victim.call("subscribe", {{"topics", {"attitude", "motion"}}})["result"]["topics"],
              json({"attitude", "motion"}));
    // It never reads: attitude lines fill its socket, then its queue.
    publish_samples(h, 1, 4000);
    std::string batch = "[";
    for (int i = 1; i <= 8; ++i) {
        batch += R"({"id":)" + std::to_string(i) +
                 R"(,"method":"speed","params":{"yaw":5,"duration_ms":1000}},)";
    }
    batch += R"({"id":9,"method":"attitude_channel"}])";
    ASSERT_TRUE(victim.send(batch + "\n"));
    ASSERT_TRUE(h.eventually([&] { return h.server->clients() == 1; }))
        << "the motion events did not overflow the victim's queue";
    EXPECT_EQ(h.server->attitude_channel_clients(), 1u)
        << "a wake block was made for a connection that had already closed";
    EXPECT_EQ(h.server->attitude_channel_failures(), 0u);  // not a shortage: not counted
}

}  // namespace
}  // namespace gport::ipc
