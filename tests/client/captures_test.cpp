// Geotags from the C++ client (issue 32) against gportd --simulate: photo
// and record with meta, captures paged by `more`/`next`, the capture topic,
// and async_captures.
#include <boost/asio/io_context.hpp>

#include "client_fixture.hpp"
#include "gport/client/async_client.hpp"

namespace gport::testing {
namespace {

using ClientCaptures = SimulatedDaemonTest;
using nlohmann::json;

TEST_F(ClientCaptures, AMetaThatIsNoObjectIsRefusedBeforeSending) {
    for (const auto* meta : {"[1]", "{", "\"text\""}) {
        try {
            client().photo(gc::CaptureOptions{meta});
            ADD_FAILURE() << meta;
        } catch (const gc::Error& e) {
            EXPECT_EQ(e.code(), static_cast<int>(gc::ErrorCode::kInvalidParams)) << meta;
        }
        EXPECT_THROW(client().record(std::nullopt, false, gc::CaptureOptions{meta}), gc::Error);
    }
    EXPECT_TRUE(client().captures().captures.empty()) << "nothing was sent";
}

TEST_F(ClientCaptures, PhotoAndRecordWithMetaAreListedPageByPage) {
    const auto photo = client().photo({R"({"lat":47.397742,"lon":8.545594,"alt_m":488.5})"});
    ASSERT_TRUE(photo.capture.has_value());
    EXPECT_EQ(photo.capture->kind, "photo");
    const auto record = client().record(true, true, {R"({"flight":"F12"})"});
    ASSERT_TRUE(record.capture.has_value());
    EXPECT_EQ(record.capture->index, photo.capture->index + 1);

    const auto first = client().captures(photo.capture->index, 1);
    ASSERT_EQ(first.captures.size(), 1U);
    EXPECT_TRUE(first.more);
    EXPECT_EQ(first.next, photo.capture->index + 1);
    EXPECT_EQ(json::parse(first.captures[0].meta)["lat"], 47.397742);
    ASSERT_TRUE(first.captures[0].client.has_value());
    EXPECT_EQ(first.captures[0].client->pid, ::getpid());
    const auto second = client().captures(first.next);
    ASSERT_EQ(second.captures.size(), 1U);
    EXPECT_FALSE(second.more);
    EXPECT_EQ(json::parse(second.captures[0].meta)["flight"], "F12");
}

TEST_F(ClientCaptures, TheCaptureTopicReachesOnCapture) {
    std::vector<gc::CaptureEntry> seen;
    client().on_capture([&](const gc::CaptureEntry& entry) { seen.push_back(entry); });
    client().subscribe({"capture"});
    const auto photo = client().photo({R"({"n":1})"});
    ASSERT_TRUE(photo.capture.has_value());
    for (int i = 0; i < 50 && seen.empty(); ++i) {
        client().dispatch(gc::Milliseconds(20));
    }
    ASSERT_EQ(seen.size(), 1U);
    EXPECT_EQ(seen[0].capture.index, photo.capture->index);
    EXPECT_EQ(seen[0].meta, R"({"n":1})");
    EXPECT_FALSE(client().next_notification(gc::Milliseconds(50)).has_value())
        << "captures never reach the Notification queue";
}

TEST_F(ClientCaptures, AsyncCapturesAndOnCapture) {
    boost::asio::io_context io;
    gc::AsyncClient async(io);
    std::optional<gc::CaptureEntry> announced;
    std::optional<gc::CapturesPage> page;
    async.on_capture([&](const gc::CaptureEntry& entry) { announced = entry; });
    async.async_connect(socket(), [&](std::optional<gc::Error> error) {
        ASSERT_FALSE(error);
        async.async_subscribe({"capture"}, std::nullopt, [&](auto e, gc::Subscription) {
            ASSERT_FALSE(e);
            async.async_photo_report({R"({"lat":1.5,"lon":2.5})"}, [&](auto pe, gc::PhotoReport) {
                ASSERT_FALSE(pe);
                async.async_captures(0, std::nullopt, [&](auto ce, gc::CapturesPage p) {
                    ASSERT_FALSE(ce);
                    page = p;
                });
            });
        });
    });
    for (int i = 0; i < 500 && !(page && announced); ++i) {
        io.run_for(std::chrono::milliseconds(10));
    }
    ASSERT_TRUE(page.has_value());
    ASSERT_TRUE(announced.has_value());
    ASSERT_FALSE(page->captures.empty());
    EXPECT_EQ(page->captures.back().capture.index, announced->capture.index);
    EXPECT_EQ(json::parse(announced->meta)["lon"], 2.5);
}

}  // namespace
}  // namespace gport::testing
