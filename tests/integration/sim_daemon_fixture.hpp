// A test fixture for end-to-end tests that need the real gport-sim, the real
// gportd on it, and one connected client, with the link up before the test
// body runs.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "harness.hpp"

namespace gport::testing {

class SimDaemonTest : public ::testing::Test {
  protected:
    void SetUp() override {
        sim_ = std::make_unique<SimProcess>(dir_);
        daemon_ = std::make_unique<DaemonProcess>(
            dir_, std::vector<std::string>{"--device", sim_->link()}, std::vector<std::string>{},
            config_extra());
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
    }

    // More config sections for gportd, as write_test_config takes them.
    virtual std::string config_extra() const { return {}; }

    TempDir dir_;
    std::unique_ptr<SimProcess> sim_;
    std::unique_ptr<DaemonProcess> daemon_;
    std::unique_ptr<Client> client_;
};

}  // namespace gport::testing
