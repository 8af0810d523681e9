// What the ipc tests of the attitude channel share: samples as the core
// publishes them, publishing through the fake core on the server's io
// thread, the result attitude_channel answers, and opening the channel on
// a connection (its two blocks, mapped read-only).
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>

#include "channel_client.hpp"
#include "server_harness.hpp"

namespace gport::testing {

inline daemon::AttitudeSample channel_sample(std::uint64_t seq, bool rates = false) {
    daemon::AttitudeSample s;
    s.seq = seq;
    s.wall = daemon::WallTime(std::chrono::microseconds(1'763'770'000'123'456LL));
    s.received = std::chrono::steady_clock::now();
    s.attitude.imu = {-1921, 250, static_cast<std::int16_t>(seq)};
    s.attitude.hall = {1, -3929, 18000};
    if (rates) {
        s.attitude.rates = protocol::AttitudeRates{{125, -5, 0}, 12, -230, 0};
    }
    return s;
}

inline void publish_samples(ServerHarness& h, std::uint64_t first, std::uint64_t count,
                            bool rates = false) {
    h.on_io([&] {
        for (auto seq = first; seq < first + count; ++seq) {
            h.api.observer->on_attitude(channel_sample(seq, rates));
        }
    });
}

// Every wake asked for so far has been made: the waker thread is idle.
inline bool wakes_done(ServerHarness& h) {
    return h.eventually([&] { return h.server->attitude_wakes_done(); });
}

inline nlohmann::json channel_result(std::uint64_t published, std::size_t descriptors) {
    return nlohmann::json{{"version", 2},
                          {"slots", 64},
                          {"size", base::ring_bytes(64)},
                          {"published", published},
                          {"descriptors", descriptors}};
}

// The ring, then the wake block, of a client whose first reply came.
struct Opened {
    std::unique_ptr<RingMapping> ring;
    std::unique_ptr<WakeMapping> wake;
};

inline Opened open_channel(DescriptorClient& client) {
    const auto reply = client.call("attitude_channel");
    EXPECT_EQ(reply["result"]["descriptors"], 2) << reply;
    const int ring = client.take_descriptor();
    const int wake = client.take_descriptor();
    Opened o{std::make_unique<RingMapping>(ring, base::ring_bytes(64)),
             std::make_unique<WakeMapping>(wake)};
    ::close(ring);
    ::close(wake);
    return o;
}

// A batch of `count` attitude_channel requests, ids 1..count, as one line.
inline std::string channel_batch(int count) {
    std::string batch = "[";
    for (int i = 1; i <= count; ++i) {
        batch += i > 1 ? "," : "";
        batch += R"({"id":)";
        batch += std::to_string(i);
        batch += R"(,"method":"attitude_channel"})";
    }
    return batch + "]\n";
}

}  // namespace gport::testing
