// gport-web's pure parts: the token file's rules, sessions and login
// limits, the outbound queue's bounds, the registry of connections, the
// options.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "gport/web/limits.hpp"
#include "gport/web/login_codes.hpp"
#include "gport/web/options.hpp"
#include "gport/web/outbox.hpp"
#include "gport/web/registry.hpp"
#include "gport/web/request_rates.hpp"
#include "gport/web/sessions.hpp"
#include "gport/web/tokens.hpp"

namespace gport::web {
namespace {

TEST(Tokens, LinesGiveRolesAndBadLinesAreNamed) {
    const auto tokens = parse_tokens(
        "# comment\ncontrol:aaaaaaaaaaaaaaaa\nview:bbbbbbbbbbbbbbbb\n"
        "cccccccccccccccc\n");
    ASSERT_EQ(tokens.size(), 3U);
    EXPECT_EQ(role_of(tokens, "aaaaaaaaaaaaaaaa"), Role::kControl);
    EXPECT_EQ(role_of(tokens, "bbbbbbbbbbbbbbbb"), Role::kView);
    EXPECT_EQ(role_of(tokens, "cccccccccccccccc"), Role::kControl);
    EXPECT_FALSE(role_of(tokens, "aaaaaaaaaaaaaaa"));
    EXPECT_FALSE(role_of(tokens, ""));
    try {
        parse_tokens("view:aaaaaaaaaaaaaaaa\nshort\n");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos);
    }
    EXPECT_THROW(parse_tokens("# nothing\n"), std::runtime_error);
    EXPECT_THROW(parse_tokens("aaaaaaaaaaaaaaaa<b>\n"), std::runtime_error);
    EXPECT_EQ(random_hex(32).size(), 64U);
    EXPECT_NE(random_hex(8), random_hex(8));
}

TEST(Sessions, AreBoundedAndExpire) {
    Sessions sessions;
    const auto t0 = Sessions::Clock::now();
    const auto first = sessions.open(Role::kControl, t0);
    EXPECT_EQ(first.size(), 64U);
    EXPECT_EQ(sessions.find(first, t0), Role::kControl);
    for (std::size_t i = 0; i < kMaxSessions; ++i) {
        sessions.open(i % 2 == 0 ? Role::kControl : Role::kView, t0 + std::chrono::seconds(1));
    }
    EXPECT_EQ(sessions.size(), kMaxSessions);
    EXPECT_FALSE(sessions.find(first, t0 + std::chrono::seconds(2)));  // the oldest went
    const auto late = sessions.open(Role::kControl, t0);
    EXPECT_FALSE(sessions.find(late, t0 + kSessionIdle + std::chrono::seconds(1)));
}

// The attacker: a view token's holder logs in 1,000 times. The sessions stay
// bounded, and the operator's control session, unused meanwhile (the page
// talks over its WebSocket), is still there for its Stop.
TEST(Sessions, AViewLoginFloodNeverEndsAControlSession) {
    Sessions sessions;
    const auto t0 = Sessions::Clock::now();
    const auto operator_session = sessions.open(Role::kControl, t0);
    for (int i = 0; i < 1000; ++i) {
        sessions.open(Role::kView, t0 + std::chrono::milliseconds(1 + i));
    }
    EXPECT_LE(sessions.size(), kMaxSessions);
    EXPECT_EQ(sessions.find(operator_session, t0 + std::chrono::seconds(2)), Role::kControl);
}

// A one-time code logs in once, with its token's role, until it expires;
// a changed digit, a code of another token file, or one claiming a longer
// life is refused.
TEST(LoginCodes, WorkOnceWithTheirTokensRoleUntilTheyExpire) {
    const std::vector<Token> tokens = {{"control-token-0123456789", Role::kControl},
                                       {"view-token-0123456789abc", Role::kView}};
    const auto now = WallClock::now();
    LoginCodes codes;
    const auto control = make_login_code(tokens[0], now);
    EXPECT_EQ(codes.redeem(tokens, control, now), Role::kControl);
    EXPECT_EQ(codes.redeem(tokens, control, now), std::nullopt) << "used";
    EXPECT_EQ(codes.redeem(tokens, make_login_code(tokens[1], now), now), Role::kView);
    const auto later = make_login_code(tokens[0], now);
    EXPECT_EQ(codes.redeem(tokens, later, now + kLoginCodeLifetime), std::nullopt) << "expired";
    auto changed = make_login_code(tokens[0], now);
    changed.back() = changed.back() == '0' ? '1' : '0';
    EXPECT_EQ(codes.redeem(tokens, changed, now), std::nullopt);
    const std::vector<Token> other = {{"another-token-0123456789", Role::kControl}};
    EXPECT_EQ(codes.redeem(tokens, make_login_code(other[0], now), now), std::nullopt);
    // Made for an hour: its MAC is right, its life is not ours.
    const auto long_lived = make_login_code(tokens[0], now + std::chrono::hours(1));
    EXPECT_EQ(codes.redeem(tokens, long_lived, now), std::nullopt);
    for (const auto* bad : {"", "x", "1.2.3", "..", "99999999999999999999.aa.bb"}) {
        EXPECT_EQ(codes.redeem(tokens, bad, now), std::nullopt) << bad;
    }
}

TEST(RequestRates, ABurstThenTheRateForEachAddressWithinItsCap) {
    RequestRates rates;
    const auto t0 = RequestRates::Clock::now();
    for (int i = 0; i < static_cast<int>(kApiRequestBurst); ++i) {
        ASSERT_FALSE(rates.take("10.0.0.1", t0)) << i;
    }
    EXPECT_EQ(rates.take("10.0.0.1", t0), 1);
    EXPECT_FALSE(rates.take("10.0.0.2", t0)) << "another address has its own";
    EXPECT_FALSE(rates.take("10.0.0.1", t0 + std::chrono::milliseconds(40)));
    for (std::size_t i = 0; i < kMaxRateAddresses + 10; ++i) {
        rates.take("192.0.2." + std::to_string(i), t0);
    }
    EXPECT_EQ(rates.addresses(), kMaxRateAddresses);
}

TEST(LoginGuard, BlocksAnAddressAfterItsFailuresUntilTheWindowEnds) {
    LoginGuard guard;
    const auto t0 = LoginGuard::Clock::now();
    for (std::size_t i = 0; i < kMaxLoginFailures; ++i) {
        EXPECT_FALSE(guard.blocked("10.0.0.1", t0));
        guard.failed("10.0.0.1", t0);
    }
    const auto wait = guard.blocked("10.0.0.1", t0 + std::chrono::seconds(10));
    ASSERT_TRUE(wait);
    EXPECT_EQ(*wait, 50);
    EXPECT_FALSE(guard.blocked("10.0.0.2", t0 + std::chrono::seconds(10)));
    EXPECT_FALSE(guard.blocked("10.0.0.1", t0 + kLoginWindow));
    EXPECT_EQ(guard.addresses(), 0U);  // forgotten once its window ended
}

TEST(LoginGuard, HasACeilingAcrossAddresses) {
    LoginGuard guard;
    const auto t0 = LoginGuard::Clock::now();
    for (std::size_t i = 0; i < kMaxLoginFailuresTotal; ++i) {
        guard.failed("10.1.0." + std::to_string(i), t0 + std::chrono::seconds(i % 2));
    }
    const auto wait = guard.blocked("10.2.0.1", t0 + std::chrono::seconds(1));
    ASSERT_TRUE(wait);
    EXPECT_EQ(*wait, 59);
    EXPECT_FALSE(guard.blocked("10.2.0.1", t0 + kLoginWindow + std::chrono::seconds(1)));
}

TEST(LoginGuard, RemembersAtMostItsCapOfAddressesTheOldestForgotten) {
    LoginGuard guard;
    const auto t0 = LoginGuard::Clock::now();
    for (int i = 0; i < 5000; ++i) {
        const auto address = "10." + std::to_string(i / 256) + ".0." + std::to_string(i % 256);
        guard.failed(address, t0 + std::chrono::milliseconds(i));
        guard.failed(address, t0 + std::chrono::milliseconds(i));
        EXPECT_LE(guard.addresses(), kMaxLoginAddresses);
    }
    EXPECT_EQ(guard.addresses(), kMaxLoginAddresses);
    for (std::size_t i = 0; i < kMaxLoginFailures; ++i) {
        guard.failed("10.99.0.1", t0 + std::chrono::seconds(6));
    }
    EXPECT_TRUE(guard.blocked("10.99.0.1", t0 + std::chrono::seconds(6)));
    EXPECT_EQ(guard.addresses(), kMaxLoginAddresses);
}

TEST(Outbox, KeepsTheNewestAttitudeAndBoundsTheRest) {
    Outbox outbox;
    for (int i = 0; i < 1000; ++i) {
        outbox.push(std::make_shared<const std::string>("a" + std::to_string(i)), true);
        outbox.push(std::make_shared<const std::string>("m" + std::to_string(i)), false);
    }
    EXPECT_EQ(outbox.size(), kMaxQueuedMessages + 1);
    EXPECT_EQ(outbox.dropped(), 999U + 1000U - kMaxQueuedMessages);
    EXPECT_EQ(*outbox.pop(), "m" + std::to_string(1000 - kMaxQueuedMessages));
    while (outbox.size() > 1) {
        outbox.pop();
    }
    EXPECT_EQ(*outbox.pop(), "a999");
    EXPECT_FALSE(outbox.pop());
}

// A connection as the registry sees it: what it was sent, whether closed.
struct FakeMember : Member {
    void close() override { closed = true; }
    void deliver(const Message& message, bool) override { got.push_back(*message); }
    bool closed = false;
    std::vector<std::string> got;
};

struct Joined {
    std::shared_ptr<FakeMember> member = std::make_shared<FakeMember>();
    std::unique_ptr<Registry::Membership> membership;
};

Joined join(Registry& registry, const std::string& peer) {
    Joined joined;
    joined.membership = registry.join(peer);
    joined.membership->hold(joined.member);
    return joined;
}

TEST(Registry, CapsEachAddressAndTheWhole) {
    Registry registry;
    std::vector<Joined> held;
    for (std::size_t i = 0; i < kMaxConnectionsPerAddress; ++i) {
        ASSERT_EQ(registry.admit("10.0.0.1"), Admission::kServe);
        held.push_back(join(registry, "10.0.0.1"));
        held.back().membership->authenticate();
    }
    EXPECT_EQ(registry.admit("10.0.0.1"), Admission::kTooManyFromPeer);
    for (std::size_t i = held.size(); i < kMaxConnections; ++i) {
        const auto peer = "10.0.1." + std::to_string(i);
        ASSERT_EQ(registry.admit(peer), Admission::kServe);
        held.push_back(join(registry, peer));
        held.back().membership->authenticate();
    }
    EXPECT_EQ(registry.admit("10.0.2.1"), Admission::kFull);
    held.pop_back();  // one leaves: room again
    EXPECT_EQ(registry.size(), kMaxConnections - 1);
    EXPECT_EQ(registry.admit("10.0.2.1"), Admission::kServe);
    held.clear();
    EXPECT_EQ(registry.size(), 0U);
    EXPECT_EQ(registry.from("10.0.0.1"), 0U);
}

TEST(Registry, ANewcomerTakesTheRoomOfTheOldestUnauthenticatedNeverATrustedOne) {
    Registry registry;
    auto operator_page = join(registry, "192.168.1.2");
    operator_page.membership->authenticate();
    std::vector<Joined> idle;
    for (std::size_t i = 0; i < kMaxUnauthenticatedConnections; ++i) {
        idle.push_back(join(registry, "10.0.0." + std::to_string(i)));
    }
    EXPECT_EQ(registry.unauthenticated(), kMaxUnauthenticatedConnections);
    EXPECT_EQ(registry.admit("10.0.9.9"), Admission::kServe);
    EXPECT_TRUE(idle.front().member->closed);  // the oldest, closed at once
    EXPECT_FALSE(idle[1].member->closed);
    EXPECT_FALSE(operator_page.member->closed);
    // Counted until its operations end, but no longer among the new ones.
    EXPECT_EQ(registry.unauthenticated(), kMaxUnauthenticatedConnections - 1);
    EXPECT_EQ(registry.size(), kMaxUnauthenticatedConnections + 1);
    idle.erase(idle.begin());
    EXPECT_EQ(registry.size(), kMaxUnauthenticatedConnections);
}

// The attacker without a token: the operator's page and two viewers hold 21
// logged-in connections, the attacker 43 idle ones from three addresses,
// fewer than the 48 not-yet-logged-in ones that make room. Every slot is
// taken: the operator's new connection (its Stop, its live socket again)
// still gets in, in place of the oldest idle one.
TEST(Registry, WhenFullANewcomerStillTakesTheRoomOfAnUnauthenticatedOne) {
    Registry registry;
    std::vector<Joined> held;
    for (std::size_t i = 0; i < 21; ++i) {
        held.push_back(join(registry, "192.168.1." + std::to_string(2 + i % 3)));
        held.back().membership->authenticate();
    }
    std::vector<Joined> idle;
    for (std::size_t i = 0; i < kMaxConnections - 21; ++i) {
        idle.push_back(join(registry, "10.0." + std::to_string(i % 3) + "." + std::to_string(i)));
    }
    ASSERT_EQ(registry.size(), kMaxConnections);
    ASSERT_LT(registry.unauthenticated(), kMaxUnauthenticatedConnections);
    EXPECT_EQ(registry.admit("192.168.1.2"), Admission::kServe);
    EXPECT_TRUE(idle.front().member->closed) << "the oldest idle connection makes room";
    for (const auto& h : held) {
        EXPECT_FALSE(h.member->closed);
    }
    // Only when every slot is logged in is a newcomer refused.
    idle.clear();
    while (registry.size() < kMaxConnections) {
        held.push_back(join(registry, "172.16.0." + std::to_string(registry.size())));
        held.back().membership->authenticate();
    }
    EXPECT_EQ(registry.admit("10.0.9.9"), Admission::kFull);
}

TEST(Registry, BroadcastsToListeningMembersAndClosesAll) {
    Registry registry;
    auto page = join(registry, "10.0.0.1");
    auto other = join(registry, "10.0.0.2");
    auto http = join(registry, "10.0.0.3");
    page.membership->listen(true);
    other.membership->listen(true);
    EXPECT_EQ(registry.listening(), 2U);
    registry.broadcast(std::make_shared<const std::string>("one"), false);
    other.membership->listen(false);
    registry.broadcast(std::make_shared<const std::string>("two"), true);
    EXPECT_EQ(page.member->got, (std::vector<std::string>{"one", "two"}));
    EXPECT_EQ(other.member->got, (std::vector<std::string>{"one"}));
    EXPECT_TRUE(http.member->got.empty());
    page.member.reset();  // on its way out: skipped, not called
    registry.broadcast(std::make_shared<const std::string>("three"), false);
    page.membership.reset();
    EXPECT_EQ(registry.listening(), 0U);
    registry.close_all();
    EXPECT_TRUE(other.member->closed);
    EXPECT_TRUE(http.member->closed);
}

std::string no_env(const char*) {
    return "";
}

TEST(Options, DefaultsAndListenAddresses) {
    const std::vector<std::string> none;
    const auto parsed = parse_options(none, no_env);
    ASSERT_TRUE(parsed.options);
    EXPECT_EQ(parsed.options->address, "127.0.0.1");
    EXPECT_EQ(parsed.options->port, kDefaultPort);
    EXPECT_EQ(parsed.options->socket, "/run/gportd.sock");
    const std::vector<std::string> v6 = {"--listen", "[::1]:0", "--allow-host", "gimbal.local"};
    const auto other = parse_options(v6, no_env);
    EXPECT_EQ(other.options->address, "::1");
    EXPECT_EQ(other.options->port, 0);
    EXPECT_EQ(other.options->allow_hosts, std::vector<std::string>{"gimbal.local"});
    for (const auto& bad : {std::vector<std::string>{"--listen", "localhost:80"},
                            {"--listen", "1.2.3.4:70000"},
                            {"--bogus"},
                            {"--allow-host", "http://x/"}}) {
        EXPECT_THROW(parse_options(bad, no_env), std::invalid_argument) << bad[0];
    }
}

}  // namespace
}  // namespace gport::web
