// The wire contract's own consistency, and the parts that take their names
// and values from it: libgport-client's ErrorCode and Counters (installed,
// so their values and layout are its ABI) and the core's Counters.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "gport/client/error.hpp"
#include "gport/client/types.hpp"
#include "gport/contract/counters.hpp"
#include "gport/contract/errors.hpp"
#include "gport/contract/limits.hpp"
#include "gport/contract/names.hpp"
#include "gport/daemon/api.hpp"

namespace {

namespace contract = gport::contract;

struct Entry {
    std::string name;
    int code;
};

std::vector<Entry> error_codes() {
    return {
#define GPORT_TEST_ERROR(name, code, meaning) Entry{#name, code},
        GPORT_CONTRACT_ERROR_CODES(GPORT_TEST_ERROR)
#undef GPORT_TEST_ERROR
    };
}

TEST(Contract, EveryErrorCodeHasOneNameAndIsAJsonRpcCode) {
    std::set<int> codes;
    std::set<std::string> names;
    for (const auto& [name, code] : error_codes()) {
        EXPECT_TRUE(codes.insert(code).second) << code << " has two names";
        EXPECT_TRUE(names.insert(name).second) << name << " names two codes";
        const bool predefined = code == -32700 || (code >= -32603 && code <= -32600);
        const bool server = code >= -32099 && code <= -32000;
        EXPECT_TRUE(predefined || server) << name << " = " << code;
    }
    EXPECT_EQ(codes.size(), 12u);
}

// The installed enum keeps its names and values (its ABI): each comes from
// the contract's entry of the same name; the library's own three stay apart.
TEST(Contract, ClientErrorCodesAreTheContractsPlusTheLibrarysOwn) {
    using gport::client::ErrorCode;
#define GPORT_TEST_CLIENT_CODE(name, code, meaning) \
    EXPECT_EQ(static_cast<int>(ErrorCode::name), code) << #name;
    GPORT_CONTRACT_ERROR_CODES(GPORT_TEST_CLIENT_CODE)
#undef GPORT_TEST_CLIENT_CODE
    EXPECT_EQ(static_cast<int>(ErrorCode::kNoSlot), -32004);
    EXPECT_EQ(static_cast<int>(ErrorCode::kTooManyRequests), -32005);
    EXPECT_EQ(static_cast<int>(ErrorCode::kConfigInvalid), -32006);
    EXPECT_EQ(static_cast<int>(ErrorCode::kTransport), -1);
    EXPECT_EQ(static_cast<int>(ErrorCode::kBadReply), -2);
    EXPECT_EQ(static_cast<int>(ErrorCode::kTimeout), -3);
}

// The core's error codes are the wire's: ipc sends them as they are.
TEST(Contract, TheCoresErrorCodeIsTheWireCode) {
    const gport::daemon::CommandError error{gport::daemon::ErrorCode::kTooManyRequests, "x"};
    EXPECT_EQ(static_cast<int>(error.code), -32005);
    EXPECT_EQ(contract::rpc_error::kBusy, -32003);
}

// client::Counters (part of libgport-client's ABI) has 19 fields of 8 bytes
// in the contract's order; the core keeps all but the transport's last one.
TEST(Contract, CountersFollowTheOneFieldList) {
    std::vector<std::string> fields;
#define GPORT_TEST_COUNTER(name) fields.push_back(#name);
    GPORT_CONTRACT_COUNTERS(GPORT_TEST_COUNTER)
#undef GPORT_TEST_COUNTER
    ASSERT_EQ(fields.size(), 19u);
    EXPECT_EQ(fields.front(), "frames_in");
    EXPECT_EQ(fields.back(), "dropped_notifications");
    EXPECT_EQ(sizeof(gport::client::Counters), 19 * sizeof(std::uint64_t));
    EXPECT_EQ(sizeof(gport::daemon::Counters), 18 * sizeof(std::uint64_t));
    // The order is the layout (1.x's): frames_in first, settings_timeouts
    // 18th, dropped_notifications last.
    using Client = gport::client::Counters;
    EXPECT_EQ(offsetof(Client, frames_in), 0u);
    EXPECT_EQ(offsetof(Client, settings_timeouts), 17 * sizeof(std::uint64_t));
    EXPECT_EQ(offsetof(Client, dropped_notifications), 18 * sizeof(std::uint64_t));
    const Client c;
    EXPECT_EQ(c.frames_in, 0u);
    EXPECT_EQ(c.dropped_notifications, 0u);
}

TEST(Contract, NamesAreDistinct) {
    const std::set<std::string_view> methods(contract::kMethods.begin(), contract::kMethods.end());
    EXPECT_EQ(methods.size(), contract::kMethods.size());
    const std::set<std::string_view> topics(contract::kTopics.begin(), contract::kTopics.end());
    EXPECT_EQ(topics.size(), contract::kTopics.size());
    EXPECT_EQ(contract::kTopics.size(), 4u);
}

TEST(Contract, RangesAreOrdered) {
    EXPECT_LT(contract::kMinRateHz, contract::kMaxRateHz);
    EXPECT_DOUBLE_EQ(contract::kMaxDegrees * 100, 32767.0);
    EXPECT_GT(contract::kMaxDurationMs, 600'000) << "above gportd's largest max_duration_ms";
}

}  // namespace
