// The per-client bounded queue: attitude dropped first, newest kept, replies
// never lost silently.
#include "gport/ipc/outbox.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace gport::ipc {
namespace {

using nlohmann::json;

AttitudeLine attitude(int seq) {
    daemon::AttitudeSample s;
    s.seq = static_cast<std::uint64_t>(seq);
    return attitude_line(s);
}

Line reply(int id) {
    return std::make_shared<const std::string>(
        json({{"jsonrpc", "2.0"}, {"id", id}, {"result", true}}).dump() + "\n");
}

std::vector<json> drain(Outbox& box) {
    std::vector<Line> lines;
    box.take(lines, 1000);
    std::vector<json> out;
    for (const auto& l : lines) {
        out.push_back(json::parse(*l));
    }
    return out;
}

TEST(Outbox, KeepsTheNewestAttitudeAndReportsDrops) {
    Outbox box(3);
    for (int seq = 1; seq <= 5; ++seq) {
        box.push_attitude(attitude(seq));
    }
    EXPECT_EQ(box.dropped(), 2u);
    auto lines = drain(box);
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0]["params"]["seq"], 3);
    EXPECT_EQ(lines[2]["params"]["seq"], 5);
    EXPECT_EQ(lines[2]["params"]["dropped"], 2);
    EXPECT_FALSE(lines[0]["params"].contains("dropped"));
    // Reported once: the next one is plain again.
    box.push_attitude(attitude(6));
    EXPECT_FALSE(drain(box)[0]["params"].contains("dropped"));
}

TEST(Outbox, RepliesPushOutAttitudesAndFailOnlyWhenNoneLeft) {
    Outbox box(2);
    box.push_attitude(attitude(1));
    EXPECT_TRUE(box.push(reply(1)));
    EXPECT_TRUE(box.push(reply(2)));  // the attitude made room
    EXPECT_EQ(box.dropped(), 1u);
    EXPECT_FALSE(box.push(reply(3)));
    box.push_attitude(attitude(2));  // no room and nothing older: this one goes
    EXPECT_EQ(box.dropped(), 2u);
    auto lines = drain(box);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0]["id"], 1);
    EXPECT_EQ(lines[1]["id"], 2);
    box.push_attitude(attitude(3));
    EXPECT_EQ(drain(box)[0]["params"]["dropped"], 2);
}

TEST(Outbox, ByteLimitBoundsMemoryToo) {
    Outbox box(1000, 1024);
    int pushed = 0;
    while (box.push(reply(pushed))) {
        ++pushed;
    }
    EXPECT_LE(box.bytes(), 1024u);
    EXPECT_GT(pushed, 10);
}

TEST(Outbox, TakeMovesWholeLinesInOrder) {
    Outbox box(10);
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(box.push(reply(i)));
    }
    std::vector<Line> lines;
    box.take(lines, 2);
    EXPECT_EQ(lines.size(), 2u);
    EXPECT_EQ(box.size(), 3u);
    EXPECT_EQ(json::parse(*lines[1])["id"], 1);
}

TEST(Outbox, ALineWithDescriptorsIsNeverTakenIntoABatch) {
    Outbox box(10);
    ASSERT_TRUE(box.push(reply(1)));
    ASSERT_TRUE(box.push(reply(2), 1));
    ASSERT_TRUE(box.push(reply(3)));
    std::vector<Line> lines;
    box.take(lines, 10);
    ASSERT_EQ(lines.size(), 1u);  // stops before the line with a descriptor
    EXPECT_EQ(box.front_descriptors(), 1u);
    lines.clear();
    box.take(lines, 10);
    EXPECT_TRUE(lines.empty());
    EXPECT_EQ(json::parse(*box.pop_front())["id"], 2);
    EXPECT_EQ(box.front_descriptors(), 0u);
    box.take(lines, 10);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(json::parse(*lines[0])["id"], 3);
    EXPECT_TRUE(box.empty());
    EXPECT_EQ(box.bytes(), 0u);
}

TEST(Outbox, ReplacingTheFrontKeepsTheByteCountAndDropsItsDescriptors) {
    Outbox box(10);
    ASSERT_TRUE(box.push(reply(1), 2));
    box.replace_front(std::make_shared<const std::string>("{\"id\":1,\"error\":{}}\n"));
    EXPECT_EQ(box.front_descriptors(), 0u);
    EXPECT_EQ(box.bytes(), box.front()->size());
    EXPECT_EQ(box.reply_bytes(), box.bytes());
}

}  // namespace
}  // namespace gport::ipc
