// The blocking Client against a hostile gportd (issue 22 item 7): a line
// without end, JSON nested a million deep, a server that never answers or
// never reads, a flood of notifications nobody takes. Each test performs
// the attack and checks the client ends it with a clear Error, in bounded
// memory, without hanging or crashing.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <utility>
#include <variant>

#include "connection.hpp"
#include "gport/client/client.hpp"
#include "hostile_server.hpp"

namespace gport::testing {
namespace {

namespace gc = gport::client;
using nlohmann::json;
using namespace std::chrono_literals;

// The Error a call throws (fails the test when it throws none).
template <typename F>
gc::Error error_of(F&& call) {
    try {
        std::forward<F>(call)();
    } catch (const gc::Error& e) {
        return e;
    }
    ADD_FAILURE() << "no error";
    return gc::Error(0, "none");
}

bool mentions(const gc::Error& e, const std::string& text) {
    return e.message().find(text) != std::string::npos;
}

TEST(HostileServer, LineWithoutEndStopsAtTheLineLimit) {
    HostileServer server([](HostilePeer& peer, const json&) { peer.stream(400 * kMiB); });
    auto client = gc::Client::connect(server.path());
    const auto before = reset_peak_rss();
    const auto e = error_of([&] { client.status(); });
    const auto growth = peak_rss_growth_kib(before);
    std::printf("400 MB line: peak RSS grew %llu KiB; the server sent %llu bytes\n",
                static_cast<unsigned long long>(growth),
                static_cast<unsigned long long>(server.bytes_sent()));
    EXPECT_TRUE(e.transport()) << e.what();
    EXPECT_TRUE(mentions(e, "16777216")) << "names the limit: " << e.message();
    EXPECT_FALSE(client.connected());
    EXPECT_LT(server.bytes_sent(), 64 * kMiB) << "the client stopped reading at the limit";
    if (kRssMeasured) {
        EXPECT_LT(growth, 64 * 1024) << "KiB of peak RSS growth";
    }
}

TEST(HostileServer, JsonNestedAMillionDeepEndsTheConnection) {
    HostileServer server([](HostilePeer& peer, const json&) {
        peer.send(std::string(1'000'000, '[') + std::string(1'000'000, ']') + "\n");
    });
    auto client = gc::Client::connect(server.path());
    const auto e = error_of([&] { client.status(); });
    EXPECT_TRUE(e.transport()) << e.what();
    EXPECT_TRUE(mentions(e, "nested deeper than 64")) << e.message();
    EXPECT_FALSE(client.connected());
}

TEST(HostileServer, ALineAtTheLimitIsReadAndOneByteMoreIsNot) {
    // {"jsonrpc":"2.0","id":N,"result":{"pad":"xxx...x"}} of exactly kLineLimit bytes.
    const auto line_of = [](const json& request, std::size_t length) {
        auto message =
            json{{"jsonrpc", "2.0"}, {"id", request.at("id")}, {"result", {{"pad", ""}}}};
        message["result"]["pad"] = std::string(length - message.dump().size(), 'x');
        return message.dump() + "\n";
    };
    HostileServer server([&](HostilePeer& peer, const json& request) {
        const bool over = request.at("method") == "photo";
        peer.send(line_of(request, gc::kLineLimit + (over ? 1 : 0)));
    });
    auto connection = gc::Connection::open(server.path());
    const auto reply = connection.call("status", json::object());
    ASSERT_TRUE(reply.has_value());
    EXPECT_EQ(reply->dump().size(), gc::kLineLimit);
    EXPECT_FALSE(connection.call("photo", json::object()).has_value());
    EXPECT_TRUE(connection.closed());
    EXPECT_NE(connection.failure().find("16777216"), std::string::npos) << connection.failure();
}

// The reply nests as deep as allowed: read; one level more: refused.
TEST(HostileServer, NestingAtTheLimitIsReadAndOneLevelMoreIsNot) {
    // The reply object, then depth - 1 arrays around a string full of brackets.
    const auto reply = [](const json& request, std::size_t depth) {
        return R"({"jsonrpc":"2.0","id":)" + request.at("id").dump() + R"(,"result":)" +
               std::string(depth - 1, '[') + R"("[{\"]")" + std::string(depth - 1, ']') + "}\n";
    };
    HostileServer server([&](HostilePeer& peer, const json& request) {
        peer.send(reply(request, gc::kNestingLimit + (request.at("method") == "photo" ? 1 : 0)));
    });
    auto connection = gc::Connection::open(server.path());
    ASSERT_TRUE(connection.call("status", json::object()).has_value())
        << "brackets inside strings do not count: " << connection.failure();
    EXPECT_FALSE(connection.call("photo", json::object()).has_value());
    EXPECT_NE(connection.failure().find("nested deeper than 64"), std::string::npos)
        << connection.failure();
}

// The stack overflow of issue 22: a reply whose result nests a million deep.
TEST(HostileServer, AReplyNestedAMillionDeepEndsTheConnection) {
    for (const auto& brackets : {std::pair{"[", "]"}, std::pair{R"({"a":)", "}"}}) {
        // (not a structured binding: clang 14 cannot capture one in a lambda)
        const char* open = brackets.first;
        const char* close = brackets.second;
        HostileServer server([&](HostilePeer& peer, const json& request) {
            std::string deep;
            for (int i = 0; i < 1'000'000; ++i) {
                deep += open;
            }
            deep += "1";
            for (int i = 0; i < 1'000'000; ++i) {
                deep += close;
            }
            peer.send(R"({"jsonrpc":"2.0","id":)" + request.at("id").dump() + R"(,"result":)" +
                      deep + "}\n");
        });
        auto client = gc::Client::connect(server.path());
        const auto e = error_of([&] { client.status(); });
        EXPECT_TRUE(e.transport()) << e.what();
        EXPECT_TRUE(mentions(e, "nested deeper than 64")) << e.message();
    }
}

TEST(HostileServer, LinesThatAreNotJsonObjectsEndTheConnection) {
    const std::pair<std::string, std::string> cases[] = {
        {"{\"jsonrpc\":\"2.0\",\"id\":1,\"result\":}\n", "not JSON"},
        {"{\"jsonrpc\":\"2.0\",\"id\":1,\"result\":\"caf\xe9\"}\n", "UTF-8"},
        {"[1,2,3]\n", "not a JSON object (array)"},
        {"\"hello\"\n", "not a JSON object (string)"},
    };
    for (const auto& [line_text, reason] : cases) {
        const std::string& line = line_text;  // captured below: clang 14 cannot capture a binding
        HostileServer server([&](HostilePeer& peer, const json&) { peer.send(line); });
        auto client = gc::Client::connect(server.path());
        const auto e = error_of([&] { client.status(); });
        EXPECT_TRUE(e.transport()) << e.what();
        EXPECT_TRUE(mentions(e, reason)) << reason << ": " << e.message();
        EXPECT_FALSE(client.connected());
        EXPECT_TRUE(error_of([&] { client.status(); }).transport()) << "stays closed";
    }
}

TEST(HostileServer, ASilentServerGivesATimeoutAndTheConnectionStays) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        if (request.at("method") == "photo") {
            peer.reply(request, {{"sent", true}});
        }
    });
    auto client = gc::Client::connect(server.path());
    EXPECT_EQ(client.call_timeout(), gc::kDefaultCallTimeout);
    EXPECT_EQ(gc::kDefaultCallTimeout, 10s);
    client.set_call_timeout(200ms);
    const auto e = error_of([&] { client.status(); });
    EXPECT_TRUE(e.is(gc::ErrorCode::kTimeout)) << e.what();
    EXPECT_EQ(e.code(), -3);
    EXPECT_TRUE(mentions(e, "no reply to status within 200 ms")) << e.message();
    EXPECT_TRUE(client.connected()) << "a timeout leaves the connection usable";
    EXPECT_NO_THROW(client.photo());
}

// A flood of notifications that never ends with the reply cannot hold the
// call past its timeout.
TEST(HostileServer, AnEndlessFloodDoesNotHoldACallPastItsTimeout) {
    HostileServer server([](HostilePeer& peer, const json&) {
        for (std::uint64_t seq = 1; peer.send_line(attitude_notification(seq)); ++seq) {
        }
    });
    auto client = gc::Client::connect(server.path());
    client.set_call_timeout(300ms);
    // Every call times out while the flood goes on; on a slow machine (or
    // under qemu-user) it takes more than one call's 300 ms before the flood
    // has overrun the client's queue and notifications are dropped.
    for (int call = 0; call < 50 && client.dropped_notifications() == 0; ++call) {
        ASSERT_TRUE(error_of([&] { client.status(); }).is(gc::ErrorCode::kTimeout));
    }
    EXPECT_GT(client.dropped_notifications(), 0U);
}

// Notifications written in bulk, for up to 30 s or until the client leaves:
// each write is whole lines and at most one socket buffer (an skb of a Unix
// stream socket holds up to ~48 KiB), so what the client can read always
// ends with a complete line. `over` turns true when the flood ends.
HostileServer::Script bulk_flood(std::atomic<bool>& over) {
    return [&over](HostilePeer& peer, const json&) {
        std::string chunk;
        for (std::uint64_t seq = 1;; ++seq) {
            const auto line = attitude_notification(seq).dump() + "\n";
            if (chunk.size() + line.size() > 30 * 1024) {
                break;
            }
            chunk += line;
        }
        const auto end = std::chrono::steady_clock::now() + 30s;
        while (std::chrono::steady_clock::now() < end && peer.send(chunk)) {
        }
        over = true;
    };
}

// A program that takes a little time per notification (here 50 us) reads
// slower than the server writes: the socket is never empty.
void slow_handling() {
    std::this_thread::sleep_for(50us);
}

// Before: the deadline was looked at only when the socket had nothing more
// to read, so a server that kept it full held the call until it stopped.
TEST(HostileServer, ABulkFloodDoesNotHoldACallPastItsTimeout) {
    std::atomic<bool> over{false};
    HostileServer server(bulk_flood(over));
    auto client = gc::Client::connect(server.path());
    std::size_t notifications = 0;
    client.on_notification([&](const gc::Notification&) {
        ++notifications;
        slow_handling();
    });
    client.set_call_timeout(300ms);
    const auto e = error_of([&] { client.status(); });
    EXPECT_TRUE(e.is(gc::ErrorCode::kTimeout)) << e.what();
    EXPECT_FALSE(over) << "the call returned only when the flood ended";
    EXPECT_GT(notifications, 0U);
}

// Ctrl-C in gportctl: interrupted() is looked at after every message (it
// was only when the buffer ran out of complete lines, once per 64 KiB read).
TEST(HostileServer, ABulkFloodDoesNotHoldAnInterruptedCall) {
    std::atomic<bool> over{false};
    HostileServer server(bulk_flood(over));
    auto connection = gc::Connection::open(server.path());
    connection.set_call_timeout(std::nullopt);
    const auto asked = std::chrono::steady_clock::now() + 300ms;
    connection.interrupted = [&] { return std::chrono::steady_clock::now() >= asked; };
    std::size_t notifications = 0;
    const auto reply = connection.call("status", json::object(), [&](const json&) {
        ++notifications;
        slow_handling();
    });
    EXPECT_FALSE(reply.has_value());
    EXPECT_FALSE(over) << "the call returned only when the flood ended";
    EXPECT_GT(notifications, 0U);
}

TEST(HostileServer, AWaitCallMayTakeLongerThanTheCallTimeout) {
    HostileServer server([](HostilePeer& peer, const json& request) {
        std::this_thread::sleep_for(400ms);  // the motion runs
        peer.reply(request, {{"sent", true},
                             {"angle", {{"roll", 0}, {"pitch", 0}, {"yaw", 10}}},
                             {"clamped", json::array()},
                             {"ended", {{"reason", "reached"}, {"elapsed_ms", 390}}}});
    });
    auto client = gc::Client::connect(server.path());
    client.set_call_timeout(100ms);
    const auto result = client.angle({.yaw = 10}, {.wait = true});
    ASSERT_TRUE(result.ended.has_value());
    EXPECT_EQ(result.ended->reason, "reached");
}

TEST(HostileServer, AServerThatNeverReadsCannotHoldACall) {
    HostileServer server(nullptr);
    auto connection = gc::Connection::open(server.path());
    connection.set_call_timeout(300ms);
    const json big = {{"pad", std::string(16 * kMiB, 'x')}};  // more than the socket buffers
    EXPECT_FALSE(connection.call("status", big).has_value());
    EXPECT_TRUE(connection.closed());
    EXPECT_NE(connection.failure().find("did not read the request to status"), std::string::npos)
        << connection.failure();
}

TEST(HostileServer, AFloodNobodyTakesIsBoundedAndCounted) {
    // Unbounded, 300,000 notifications would hold ~80 MiB.
    constexpr std::uint64_t kFlood = kRssMeasured ? 300'000 : 20'000;
    HostileServer server([](HostilePeer& peer, const json& request) {
        peer.send_line({{"jsonrpc", "2.0"},
                        {"method", "link"},
                        {"params", {{"state", "up"}, {"reason", ""}}}});
        std::string batch;
        for (std::uint64_t seq = 1; seq <= kFlood; ++seq) {
            batch += attitude_notification(seq).dump() + "\n";
            if (batch.size() > kMiB) {
                peer.send(batch);
                batch.clear();
            }
        }
        peer.send(batch);
        peer.reply(request, {{"sent", true}});
    });
    auto client = gc::Client::connect(server.path());
    client.set_call_timeout(std::nullopt);  // the flood takes what the machine needs
    const auto before = reset_peak_rss();
    client.photo();
    const auto growth = peak_rss_growth_kib(before);
    std::printf("flood of %llu notifications: peak RSS grew %llu KiB\n",
                static_cast<unsigned long long>(kFlood), static_cast<unsigned long long>(growth));
    EXPECT_EQ(client.dropped_notifications(), kFlood - gc::kNotificationQueueLimit);
    if (kRssMeasured) {
        EXPECT_LT(growth, 64 * 1024) << "KiB of peak RSS growth";
    }
    const auto first = client.next_notification(0ms);
    ASSERT_TRUE(first.has_value());
    EXPECT_TRUE(std::holds_alternative<gc::LinkEvent>(*first))
        << "a flood of one kind keeps others";
    std::uint64_t expected = kFlood - gc::kNotificationQueueLimit + 1;  // the newest are kept
    while (const auto n = client.next_notification(0ms)) {
        ASSERT_TRUE(std::holds_alternative<gc::AttitudeSample>(*n));
        EXPECT_EQ(std::get<gc::AttitudeSample>(*n).seq, expected++);
    }
    EXPECT_EQ(expected, kFlood + 1);
}

// Link events whose reason is a 1 MiB string: at most kLineLimit bytes of
// them wait, however many came.
TEST(HostileServer, LongNotificationsAreBoundedInBytesToo) {
    constexpr std::size_t kEvents = kRssMeasured ? 256 : 32;
    const auto line = json{{"jsonrpc", "2.0"},
                           {"method", "link"},
                           {"params", {{"state", "down"}, {"reason", std::string(kMiB, 'r')}}}}
                          .dump() +
                      "\n";
    HostileServer server([&](HostilePeer& peer, const json& request) {
        for (std::size_t i = 0; i < kEvents; ++i) {
            peer.send(line);
        }
        peer.reply(request, {{"sent", true}});
    });
    auto client = gc::Client::connect(server.path());
    client.set_call_timeout(std::nullopt);  // the flood takes what the machine needs
    const auto before = reset_peak_rss();
    client.photo();
    const auto growth = peak_rss_growth_kib(before);
    std::size_t kept = 0;
    while (client.next_notification(0ms)) {
        ++kept;
    }
    std::printf("%zu link events of 1 MiB: %zu kept, peak RSS grew %llu KiB\n", kEvents, kept,
                static_cast<unsigned long long>(growth));
    EXPECT_LE(kept, 16U);
    EXPECT_EQ(client.dropped_notifications(), kEvents - kept);
    if (kRssMeasured) {
        EXPECT_LT(growth, 64 * 1024) << "KiB of peak RSS growth (unbounded: 256 MiB)";
    }
}

TEST(HostileServer, ALineCutByTheServerClosingIsNotAMessage) {
    HostileServer server([](HostilePeer& peer, const json&) {
        peer.send(R"({"jsonrpc":"2.0","id":1,"res)");
        peer.hang_up();
    });
    auto client = gc::Client::connect(server.path());
    const auto e = error_of([&] { client.status(); });
    EXPECT_TRUE(e.transport()) << e.what();
    EXPECT_FALSE(client.connected());
}

}  // namespace
}  // namespace gport::testing
