// Tests of libgport-client against the real gportd: `gportd --simulate`
// (the built-in simulated gimbal) on a socket in a temporary directory.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "gport/client/client.hpp"
#include "harness.hpp"

namespace gport::testing {

namespace gc = gport::client;

// Connects, retrying while gportd starts.
inline gc::Client connect_when_ready(const std::string& socket) {
    std::optional<gc::Client> client;
    eventually([&] {
        try {
            client.emplace(gc::Client::connect(socket));
            return true;
        } catch (const gc::Error&) {
            return false;
        }
    });
    if (!client) {
        throw std::runtime_error("gportd did not open " + socket);
    }
    return std::move(*client);
}

inline bool link_is(gc::Client& client, const std::string& state) {
    return eventually([&] { return client.status().link.state == state; });
}

// The next notification of type T, skipping others, within the timeout.
template <typename T>
std::optional<T> next_of(gc::Client& client, std::chrono::milliseconds timeout = 10s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
            deadline - std::chrono::steady_clock::now());
        auto n = client.next_notification(left);
        if (n && std::holds_alternative<T>(*n)) {
            return std::get<T>(*n);
        }
    }
    return std::nullopt;
}

// The next motion event with this change.
inline std::optional<gc::MotionEvent> next_motion(gc::Client& client, const std::string& change,
                                                  std::chrono::milliseconds timeout = 10s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        auto e =
            next_of<gc::MotionEvent>(client, std::chrono::duration_cast<std::chrono::milliseconds>(
                                                 deadline - std::chrono::steady_clock::now()));
        if (e && e->change == change) {
            return e;
        }
    }
    return std::nullopt;
}

// The API code of the Error that `call` throws, or 0 when it throws none.
template <typename F>
int error_code_of(F&& call) {
    try {
        std::forward<F>(call)();
    } catch (const gc::Error& e) {
        return e.code();
    }
    return 0;
}

// gportd --simulate and one connected Client, link up.
class SimulatedDaemonTest : public ::testing::Test {
  protected:
    void SetUp() override { start(); }

    void start(const std::string& config_extra = "") {
        daemon_ = std::make_unique<DaemonProcess>(dir_, std::vector<std::string>{"--simulate"},
                                                  std::vector<std::string>{}, config_extra);
        client_ = std::make_unique<gc::Client>(connect_when_ready(daemon_->socket()));
        ASSERT_TRUE(link_is(*client_, "up"));
    }

    gc::Client& client() { return *client_; }
    const std::string& socket() const { return daemon_->socket(); }

    TempDir dir_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<gc::Client> client_;
};

}  // namespace gport::testing
