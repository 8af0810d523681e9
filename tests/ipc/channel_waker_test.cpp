// The attitude channel's waker (ipc/src/channel_waker.hpp) from the inside:
// which connections the loop wakes itself, at once, and how one whose wakes
// are slow is handed to the waker thread.
#include "channel_waker.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <variant>
#include <vector>

#include "process.hpp"
#include "wake_block.hpp"

namespace gport::ipc::detail {
namespace {

using namespace std::chrono_literals;

ChannelWaker::Blocks make_blocks(std::size_t count) {
    ChannelWaker::Blocks blocks;
    for (std::size_t i = 0; i < count; ++i) {
        auto made = WakeBlock::make();
        EXPECT_TRUE(std::holds_alternative<std::unique_ptr<WakeBlock>>(made));
        blocks.push_back(std::move(std::get<std::unique_ptr<WakeBlock>>(made)));
    }
    return blocks;
}

std::uint32_t bumps(const ChannelWaker::Blocks& blocks, std::size_t i) {
    return blocks[i]->word().load(std::memory_order_acquire);
}

TEST(ChannelWaker, TheOldestConnectionsAreWokenOnTheLoopAtOnceTheRestByTheThread) {
    ChannelWaker waker;
    ASSERT_FALSE(waker.start());
    const auto blocks = make_blocks(ChannelWaker::kInline + 3);
    waker.set_blocks(blocks);
    EXPECT_EQ(waker.inline_count(), ChannelWaker::kInline);

    waker.signal();
    for (std::size_t i = 0; i < ChannelWaker::kInline; ++i) {
        EXPECT_EQ(bumps(blocks, i), 1u) << "connection " << i << " woken before signal() returned";
    }
    ASSERT_TRUE(testing::eventually([&] { return waker.idle(); }));
    for (std::size_t i = ChannelWaker::kInline; i < blocks.size(); ++i) {
        EXPECT_EQ(bumps(blocks, i), 1u) << "connection " << i << ", the thread's";
    }
    EXPECT_EQ(waker.handed_over(), 0u);
}

TEST(ChannelWaker, AFewConnectionsNeedNoThreadRound) {
    ChannelWaker waker;
    ASSERT_FALSE(waker.start());
    const auto blocks = make_blocks(2);
    waker.set_blocks(blocks);
    waker.signal();
    waker.signal();
    EXPECT_EQ(bumps(blocks, 0), 2u);
    EXPECT_EQ(bumps(blocks, 1), 2u);
    EXPECT_TRUE(waker.idle());
    EXPECT_EQ(waker.rounds(), 0u);
}

// Every wake counts as slow here (a threshold below zero, so even a clock
// that reads the same before and after a wake counts it): after kStrikes
// samples the loop hands both connections to the thread, which goes on
// waking them from the next sample on, not twice in the sample that handed
// them over.
TEST(ChannelWaker, AConnectionSlowToWakeOnTheLoopIsHandedToTheThreadAndStillWoken) {
    ChannelWaker waker(ChannelWaker::Clock::duration(-1));
    ASSERT_FALSE(waker.start());
    const auto blocks = make_blocks(2);
    waker.set_blocks(blocks);
    for (int i = 0; i < ChannelWaker::kStrikes; ++i) {
        waker.signal();
    }
    EXPECT_EQ(waker.handed_over(), 2u);
    EXPECT_EQ(waker.inline_count(), 0u);
    EXPECT_EQ(waker.rounds(), 0u) << "until then the loop woke them";
    EXPECT_TRUE(waker.idle()) << "the handing-over sample asked the thread for nothing";
    EXPECT_EQ(bumps(blocks, 0), static_cast<std::uint32_t>(ChannelWaker::kStrikes));

    waker.signal();
    ASSERT_TRUE(testing::eventually([&] { return waker.idle(); }));
    const auto woken = static_cast<std::uint32_t>(ChannelWaker::kStrikes + 1);
    EXPECT_EQ(bumps(blocks, 0), woken);
    EXPECT_EQ(bumps(blocks, 1), woken);
    EXPECT_GE(waker.rounds(), 1u);

    // A new set of connections keeps the strikes of those still in it.
    waker.set_blocks(blocks);
    EXPECT_EQ(waker.inline_count(), 0u);
}

TEST(ChannelWaker, CloseGivesEveryConnectionALastWake) {
    ChannelWaker waker;
    ASSERT_FALSE(waker.start());
    const auto blocks = make_blocks(ChannelWaker::kInline + 2);
    waker.set_blocks(blocks);
    waker.close();
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        EXPECT_EQ(bumps(blocks, i), 1u) << "connection " << i;
    }
    waker.signal();  // closed: nothing more
    EXPECT_EQ(bumps(blocks, 0), 1u);
}

}  // namespace
}  // namespace gport::ipc::detail
