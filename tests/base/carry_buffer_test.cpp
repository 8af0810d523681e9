#include "gport/base/carry_buffer.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <vector>

namespace gport::testing {
namespace {

// A scanner for fixed 3-byte records: it takes every whole record and
// leaves a shorter tail, the way a frame decoder leaves a partial frame.
struct Records {
    std::vector<std::vector<std::uint8_t>> seen;
    std::size_t operator()(const std::uint8_t* p, std::size_t n) {
        std::size_t used = 0;
        for (; n - used >= 3; used += 3) {
            seen.emplace_back(p + used, p + used + 3);
        }
        return used;
    }
};

std::vector<std::uint8_t> bytes(std::size_t n) {
    std::vector<std::uint8_t> out(n);
    for (std::size_t i = 0; i < n; ++i) {
        out[i] = static_cast<std::uint8_t>(i);
    }
    return out;
}

TEST(CarryBuffer, AnyChunkingGivesTheSameRecords) {
    const auto input = bytes(60);
    for (std::size_t chunk = 1; chunk <= 13; ++chunk) {
        base::CarryBuffer<6> carry;
        Records records;
        for (std::size_t at = 0; at < input.size(); at += chunk) {
            const auto n = std::min(chunk, input.size() - at);
            carry.feed(std::span(input).subspan(at, n), records);
        }
        ASSERT_EQ(records.seen.size(), 20U) << "chunk " << chunk;
        for (std::size_t r = 0; r < records.seen.size(); ++r) {
            EXPECT_EQ(records.seen[r][0], 3 * r) << "chunk " << chunk;
        }
        EXPECT_EQ(carry.held(), 0U);
    }
}

TEST(CarryBuffer, ATailIsCarriedAndCanBeDropped) {
    base::CarryBuffer<6> carry;
    Records records;
    const auto input = bytes(5);
    carry.feed(input, records);
    EXPECT_EQ(records.seen.size(), 1U);
    EXPECT_EQ(carry.held(), 2U);
    EXPECT_EQ(carry.clear(), 2U);
    EXPECT_EQ(carry.held(), 0U);
    const auto next = bytes(3);
    carry.feed(next, records);  // starts afresh: the dropped tail is gone
    ASSERT_EQ(records.seen.size(), 2U);
    EXPECT_EQ(records.seen[1], next);
}

}  // namespace
}  // namespace gport::testing
