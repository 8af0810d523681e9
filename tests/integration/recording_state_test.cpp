// Issue 12 end to end: the real gportd on the real gport-sim. The gimbal
// never reports whether it records, so gportd assumes a state from the 0x86
// toggles it sent; `record {"on": ...}` toggles only when that differs.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "harness.hpp"
#include "sim_daemon_fixture.hpp"

namespace gport::testing {
namespace {

class RecordingStateEndToEnd : public SimDaemonTest {
  protected:
    // Sends a photo as a marker and counts the record toggles the gimbal got
    // before it (frames go out in order): no timing involved.
    int toggles_before_marker() {
        EXPECT_EQ(client_->call("photo")["result"]["sent"], true);
        int toggles = 0;
        auto marker = sim_->process().wait_line([&](const std::string& line) {
            auto j = Json::parse(line, nullptr, false);
            if (!j.is_object()) {
                return false;
            }
            const auto action = j.value("action", "");
            toggles += action == "record" ? 1 : 0;
            return action == "photo";
        });
        EXPECT_TRUE(marker.has_value()) << "the photo never reached the gimbal";
        return toggles;
    }

    Json record(const Json& params) { return client_->call("record", params); }
    // The reply without the capture a toggle sent adds (captures_test.cpp checks it).
    static Json sent_and_state(const Json& reply) {
        Json result = reply["result"];
        EXPECT_EQ(result.contains("capture"), result.value("sent", false));
        result.erase("capture");
        return result;
    }
    std::string status_recording() {
        return client_->call("status")["result"].value("recording", "?");
    }
};

TEST_F(RecordingStateEndToEnd, OnOffSendOnlyTheTogglesNeeded) {
    EXPECT_EQ(status_recording(), "unknown");

    auto refused = record({{"on", true}});
    EXPECT_EQ(refused["error"]["code"], -32602);
    EXPECT_NE(refused["error"]["message"].get<std::string>().find("force"), std::string::npos);
    EXPECT_EQ(toggles_before_marker(), 0);

    EXPECT_EQ(sent_and_state(record({{"on", true}, {"force", true}})),
              Json({{"sent", true}, {"recording", "on"}}));
    EXPECT_EQ(toggles_before_marker(), 1);
    EXPECT_EQ(status_recording(), "on");

    EXPECT_EQ(record({{"on", true}})["result"], Json({{"sent", false}, {"recording", "on"}}))
        << "nothing sent: no capture";
    EXPECT_EQ(toggles_before_marker(), 0);

    EXPECT_EQ(sent_and_state(record({{"on", false}})),
              Json({{"sent", true}, {"recording", "off"}}));
    EXPECT_EQ(toggles_before_marker(), 1);
    EXPECT_EQ(status_recording(), "off");

    // A plain record toggles as before, and flips the assumed state.
    EXPECT_EQ(sent_and_state(record(nullptr)), Json({{"sent", true}, {"recording", "on"}}));
    EXPECT_EQ(toggles_before_marker(), 1);
}

}  // namespace
}  // namespace gport::testing
