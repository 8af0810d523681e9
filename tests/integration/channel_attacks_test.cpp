// The attacks of issue 22 on the shared-memory attitude channel, against
// the real gportd on gport-sim: a read-only peer parks many threads on its
// wake word (the documented reader pattern) while another reader and a
// commander carry on; a peer that left keeps its threads parked; a peer
// asks for the channel in batches of 32 and never reads (docs/api.md,
// "Shared-memory attitude channel").
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "channel_client.hpp"
#include "gport/base/futex.hpp"
#include "sim_daemon_fixture.hpp"

namespace gport::testing {
namespace {

constexpr std::size_t kRingBytes = base::ring_bytes(64);

struct AttackChannel {
    std::unique_ptr<RingMapping> ring;
    std::unique_ptr<WakeMapping> wake;
};

AttackChannel open_attack_channel(DescriptorClient& client) {
    const auto reply = client.call("attitude_channel");
    EXPECT_EQ(reply["result"]["descriptors"], 2) << reply;
    const int ring = client.take_descriptor();
    const int wake = client.take_descriptor();
    AttackChannel c{std::make_unique<RingMapping>(ring, kRingBytes),
                    std::make_unique<WakeMapping>(wake)};
    ::close(ring);
    ::close(wake);
    return c;
}

// Threads that sleep on a word and go straight back to sleep when woken,
// never passing a wake on: the attacker of problem 2. Counts its wakes.
class Parkers {
  public:
    Parkers(const std::atomic<std::uint32_t>& word, int count) : word_(word) {
        for (int i = 0; i < count; ++i) {
            threads_.emplace_back([this] {
                ++parked_;
                while (!stop_) {
                    const auto seen = word_.load();
                    if (base::futex_wait(word_, seen, std::chrono::seconds(5)) ==
                        base::FutexWait::kWoken) {
                        ++woken_;
                    }
                }
            });
        }
        while (parked_.load() < count) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    }
    ~Parkers() {
        stop_ = true;
        for (auto& t : threads_) {
            while (t.joinable()) {
                base::futex_wake_all(word_);
                t.join();
            }
        }
    }
    int woken() const { return woken_.load(); }

  private:
    const std::atomic<std::uint32_t>& word_;
    std::atomic<int> parked_{0};
    std::atomic<int> woken_{0};
    std::atomic<bool> stop_{false};
    std::vector<std::thread> threads_;
};

class ChannelAttacksTest : public SimDaemonTest {
  protected:
    std::string config_extra() const override {
        return R"("socket": {"max_clients_per_uid": 64, "max_clients": 64})";
    }
};

// Before: gportd's FUTEX_WAKE(INT_MAX) woke every parked thread 50 times a
// second on its loop. Now it wakes one per sample on the attacker's own
// word, and the attacker's threads are the attacker's problem.
TEST_F(ChannelAttacksTest, ThreadsParkedOnAWordAreWokenOnePerSampleAndNobodyElseWaits) {
    DescriptorClient attacker(daemon_->socket());
    auto parked = open_attack_channel(attacker);
    DescriptorClient reader(daemon_->socket());
    auto honest = open_attack_channel(reader);
    const auto& published_by = *parked.ring;
    Parkers parkers(parked.wake->word(), 200);
    const auto from = published_by.reader().published();
    const auto woken_before = parkers.woken();
    // The honest reader is woken by its own word, sample after sample.
    std::uint64_t cursor = 0;
    std::uint64_t missed = 0;
    int taken = 0;
    const auto reader_ring = honest.ring->reader();
    for (int waits = 0; waits < 400 && taken < 25; ++waits) {
        const auto seen = honest.wake->word().load();
        while (reader_ring.next(cursor, missed)) {
            ++taken;
        }
        base::futex_wait(honest.wake->word(), seen, std::chrono::seconds(1));
    }
    EXPECT_GE(taken, 25);
    EXPECT_EQ(missed, 0u);
    // A command goes through meanwhile.
    EXPECT_TRUE(client_->call("stop").contains("result"));
    const auto samples = published_by.reader().published() - from;
    const auto woken = static_cast<std::uint64_t>(parkers.woken() - woken_before);
    ASSERT_GT(samples, 0u);
    // One waiter per sample (and per re-park race at most one more), not 200.
    EXPECT_LE(woken, samples + 2) << samples << " samples woke " << woken << " of 200 threads";
    EXPECT_GE(woken, samples / 2) << "gportd does wake the attacker's word";
}

// Before: 8000 threads of a process already disconnected, plus one real
// holder, made one stop take over 5 s. Now the word of a connection that
// left is never touched again.
TEST_F(ChannelAttacksTest, AWordWhoseConnectionLeftIsNeverBumpedAgain) {
    auto gone = std::make_unique<DescriptorClient>(daemon_->socket());
    auto parked = open_attack_channel(*gone);
    DescriptorClient holder(daemon_->socket());
    auto held = open_attack_channel(holder);
    Parkers parkers(parked.wake->word(), 100);
    gone.reset();
    ASSERT_TRUE(eventually(
        [&] { return client_->call("status")["result"]["attitude_channel_clients"] == 1; }));
    // A round of the waker thread already under way when the connection
    // closed may bump its word one last time (channel_waker.hpp). Once the
    // holder's word moved twice more, a whole round began after the close
    // and every earlier one has ended: from then on the word must not move.
    const auto before = held.wake->word().load();
    ASSERT_TRUE(eventually([&] { return held.wake->word().load() - before >= 2; }));
    const auto word = parked.wake->word().load();
    const auto woken = parkers.woken();
    // Ten more rounds of the waker, each of which bumps the holder's word
    // (not one per sample: under load, samples published close together
    // share a round), and none the word of the connection that left.
    const auto held_word = held.wake->word().load();
    ASSERT_TRUE(eventually([&] { return held.wake->word().load() - held_word >= 10; }));
    EXPECT_EQ(parked.wake->word().load(), word);
    // The thread that last bump woke may count itself a moment late.
    EXPECT_LE(parkers.woken(), woken + 1);
    EXPECT_TRUE(client_->call("stop").contains("result"));
}

// Before: batches of 32 requests, never read, put 32 descriptors in flight
// per line until everyone got "Too many references". Now a connection has
// its two in flight once, whatever it asks.
TEST_F(ChannelAttacksTest, BatchesOfRequestsNeverReadPutOnlyTwoDescriptorsInFlight) {
    std::string batch = "[";
    for (int i = 1; i <= 32; ++i) {
        batch += i > 1 ? "," : "";
        batch += R"({"id":)";
        batch += std::to_string(i);
        batch += R"(,"method":"attitude_channel"})";
    }
    batch += "]\n";
    std::vector<std::unique_ptr<DescriptorClient>> attackers;
    for (int a = 0; a < 4; ++a) {
        attackers.push_back(std::make_unique<DescriptorClient>(daemon_->socket()));
        for (int line = 0; line < 5; ++line) {  // 160 a second is under the rate limit
            ASSERT_TRUE(attackers.back()->send(batch));
        }
    }
    std::this_thread::sleep_for(std::chrono::seconds(2));
    DescriptorClient other(daemon_->socket());
    const auto reply = other.call("attitude_channel");
    ASSERT_TRUE(reply.contains("result")) << reply;
    EXPECT_EQ(reply["result"]["descriptors"], 2);
    EXPECT_EQ(other.descriptors(), 2u);
    EXPECT_EQ(client_->call("status")["result"]["attitude_channel_failures"], 0);
    // What each attacker finally reads: one reply announcing descriptors.
    for (auto& attacker : attackers) {
        int announced = 0;
        for (int line = 0; line < 5; ++line) {
            const auto replies = attacker->next();
            ASSERT_TRUE(replies && replies->is_array());
            for (const auto& r : *replies) {
                announced += r["result"]["descriptors"] == 2 ? 1 : 0;
            }
        }
        EXPECT_EQ(announced, 1);
        EXPECT_EQ(attacker->descriptors(), 2u);
    }
}

}  // namespace
}  // namespace gport::testing
