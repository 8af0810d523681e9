// The attitude channel's edges in a connection's life: a session that
// closes in the middle of a batch, replies held behind a waiting request,
// the waker thread that makes every wake, and shutdown.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

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

// Replies leave in the order they are complete, and the descriptors go with
// the connection's first attitude_channel result made, even when a batch
// holds that result behind a member that waits (docs/api.md, "Opening
// it"): a later request is answered first, with "descriptors":0, and the
// descriptors come with the batch's line. Decided: a connection never has
// more than its two descriptors in flight, and no line announces
// descriptors it does not carry; the libraries never batch the request.
TEST(ChannelLifecycle, ABatchHeldByAWaitKeepsTheDescriptorsALaterRequestGetsNone) {
    ServerHarness h;
    DescriptorClient client(h.path());
    ASSERT_TRUE(client.send(R"([{"id":101,"method":"angle","params":{"pitch":-10,"wait":true}},)"
                            R"({"id":102,"method":"attitude_channel"}])"
                            "\n"));
    const auto later = client.call("attitude_channel");  // answered while the batch waits
    EXPECT_EQ(later["result"], channel_result(0, 0)) << later;
    EXPECT_EQ(client.descriptors(), 0u);
    ASSERT_TRUE(h.eventually([&] { return h.api.waiters.size() == 1; }));
    h.on_io([&] { h.api.end_waiter({daemon::EndReason::kReached, std::nullopt, {}}); });
    const auto batch = client.next();
    ASSERT_TRUE(batch && batch->is_array() && batch->size() == 2);
    EXPECT_EQ((*batch)[0]["id"], 101);
    EXPECT_EQ((*batch)[1]["result"], channel_result(0, 2)) << *batch;
    EXPECT_EQ(client.descriptors(), 2u);  // with the line that announced them
}

// Threads of this process (the server runs in it) with that name.
int threads_named(const std::string& name) {
    int count = 0;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
        std::string comm;
        std::getline(std::ifstream(task.path() / "comm"), comm);
        count += comm == name ? 1 : 0;
    }
    return count;
}

// The channel costs nothing until it is used: no thread before the first
// request; then one for the whole server, however many readers; joined
// when the server closes.
TEST(ChannelLifecycle, OneWakerThreadFromTheFirstRequestUntilTheServerCloses) {
    ServerHarness h;
    DescriptorClient watcher(h.path());
    EXPECT_TRUE(watcher.call("status").contains("result"));
    publish_samples(h, 1, 3);
    EXPECT_EQ(threads_named("gportd-waker"), 0);
    std::vector<std::unique_ptr<DescriptorClient>> readers;
    for (int i = 0; i < 5; ++i) {
        readers.push_back(std::make_unique<DescriptorClient>(h.path()));
        open_channel(*readers.back());
    }
    EXPECT_EQ(threads_named("gportd-waker"), 1);
    readers.clear();
    EXPECT_TRUE(h.eventually([&] { return h.server->attitude_channel_clients() == 0; }));
    EXPECT_EQ(threads_named("gportd-waker"), 1);  // kept for the next reader
    h.stop();
    // Joined by close(); the task may stay listed in /proc an instant after
    // the join returns (under qemu-user the host thread outlives the guest's).
    bool gone = false;
    for (int i = 0; i < 500 && !gone; ++i) {
        gone = threads_named("gportd-waker") == 0;
        if (!gone) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
    EXPECT_TRUE(gone) << threads_named("gportd-waker") << " waker thread(s) left";
}

}  // namespace
}  // namespace gport::ipc
