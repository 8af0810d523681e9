// Control arbitration: the order of the checks, acquire/release, preemption
// and a departing holder.
#include "gport/daemon/core/arbiter.hpp"

#include <gtest/gtest.h>

#include <string>

namespace gport::daemon {
namespace {

constexpr uid_t kCommander = 4101;
constexpr uid_t kReader = 4102;  // neither listed, nor root, nor the test's own uid

AccessPolicy commanders_only() {
    config::AccessConfig config;
    config.control_uids = {kCommander};
    return AccessPolicy(config);
}

ClientInfo client(std::uint64_t id, uid_t uid) {
    return ClientInfo{id, static_cast<pid_t>(100 + id), uid, uid, {}};
}

bool names(const CommandError& error, const std::string& text) {
    return error.message.find(text) != std::string::npos;
}

class ArbiterTest : public ::testing::Test {
  protected:
    Arbiter arbiter{commanders_only()};
    ClientInfo a = client(1, kCommander);
    ClientInfo b = client(2, kCommander);
    ClientInfo reader = client(3, kReader);
};

TEST_F(ArbiterTest, NobodyHoldsControlAtFirst) {
    EXPECT_FALSE(arbiter.holder());
    EXPECT_FALSE(arbiter.check(a, Arbiter::Needs::kAccessAndControl));
    EXPECT_FALSE(arbiter.check(b, Arbiter::Needs::kAccess));
}

TEST_F(ArbiterTest, AccessIsCheckedBeforeControl) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    const auto refused = arbiter.check(reader, Arbiter::Needs::kAccessAndControl);
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->code, ErrorCode::kPermission) << "not kBusy: access comes first";
    EXPECT_TRUE(names(*refused, std::to_string(kReader))) << refused->message;
}

TEST_F(ArbiterTest, ControlHeldByAnotherIsBusyAndNamesItsPid) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    const auto refused = arbiter.check(b, Arbiter::Needs::kAccessAndControl);
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->code, ErrorCode::kBusy);
    EXPECT_TRUE(names(*refused, "pid 101")) << refused->message;
    EXPECT_FALSE(arbiter.check(a, Arbiter::Needs::kAccessAndControl)) << "the holder may";
}

// stop: any client that may command, whoever holds control.
TEST_F(ArbiterTest, AccessOnlyIgnoresTheHolder) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    EXPECT_FALSE(arbiter.check(b, Arbiter::Needs::kAccess));
    const auto refused = arbiter.check(reader, Arbiter::Needs::kAccess);
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->code, ErrorCode::kPermission);
}

TEST_F(ArbiterTest, AcquireRecordsTheHolderOnce) {
    auto first = arbiter.acquire(a, std::nullopt);
    ASSERT_TRUE(first.ok());
    EXPECT_EQ(first->holder.id, a.id);
    EXPECT_TRUE(first->newly_held);
    ASSERT_TRUE(arbiter.holder());
    EXPECT_EQ(arbiter.holder()->id, a.id);

    auto again = arbiter.acquire(a, std::nullopt);
    ASSERT_TRUE(again.ok());
    EXPECT_FALSE(again->newly_held);
}

TEST_F(ArbiterTest, AcquireWhileAnotherHoldsIsRefused) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    auto refused = arbiter.acquire(b, std::nullopt);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kBusy);
    EXPECT_EQ(arbiter.holder()->id, a.id);
}

TEST_F(ArbiterTest, AReaderCannotAcquire) {
    auto refused = arbiter.acquire(reader, std::nullopt);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kPermission);
    EXPECT_FALSE(arbiter.holder());
}

TEST_F(ArbiterTest, AcquirePreemptsOnlyAnotherClientsMotion) {
    auto none = arbiter.acquire(a, std::nullopt);
    ASSERT_TRUE(none.ok());
    EXPECT_FALSE(none->preempts);
    auto own = arbiter.acquire(a, a);
    ASSERT_TRUE(own.ok());
    EXPECT_FALSE(own->preempts);
    auto other = arbiter.acquire(a, b);
    ASSERT_TRUE(other.ok());
    EXPECT_TRUE(other->preempts);
    EXPECT_EQ(arbiter.holder()->id, a.id) << "recorded before the motion ends";
}

TEST_F(ArbiterTest, OnlyTheHolderMayRelease) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    auto refused = arbiter.release(b);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, ErrorCode::kBusy);
    EXPECT_TRUE(names(refused.error(), "only it may release")) << refused.error().message;

    auto released = arbiter.release(a);
    ASSERT_TRUE(released.ok());
    ASSERT_TRUE(released.value());
    EXPECT_EQ(released.value()->id, a.id);
    EXPECT_FALSE(arbiter.holder());
}

// Release checks control only: releasing what nobody holds is harmless.
TEST_F(ArbiterTest, ReleasingWhatNobodyHoldsSucceeds) {
    auto released = arbiter.release(reader);
    ASSERT_TRUE(released.ok());
    EXPECT_FALSE(released.value());
}

TEST_F(ArbiterTest, AHolderThatGoesAwayFreesControl) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    EXPECT_FALSE(arbiter.client_gone(b));
    EXPECT_TRUE(arbiter.holder());
    EXPECT_TRUE(arbiter.client_gone(a));
    EXPECT_FALSE(arbiter.holder());
    EXPECT_FALSE(arbiter.check(b, Arbiter::Needs::kAccessAndControl));
}

// Reload: a fresh policy decides again; control stays with its holder.
TEST_F(ArbiterTest, ANewPolicyKeepsTheHolder) {
    ASSERT_TRUE(arbiter.acquire(a, std::nullopt).ok());
    EXPECT_TRUE(arbiter.may_command(b));
    config::AccessConfig config;
    config.control_uids = {kReader};
    arbiter.set_policy(AccessPolicy(config));
    EXPECT_FALSE(arbiter.may_command(b)) << "no cached decision survives";
    EXPECT_TRUE(arbiter.may_command(reader));
    ASSERT_TRUE(arbiter.holder());
    EXPECT_EQ(arbiter.holder()->id, a.id);
}

}  // namespace
}  // namespace gport::daemon
