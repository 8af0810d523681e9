// serial_candidates() on a made-up /dev and /sys: which names count, in
// which order, and the hint a missing device's log line carries.
#include "gport/daemon/serial_candidates.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace gport::daemon {
namespace {

namespace fs = std::filesystem;

class FakeTree : public ::testing::Test {
  protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() / ("gport-candidates-" + std::to_string(::getpid()));
        fs::remove_all(root_);
        fs::create_directories(dev());
        fs::create_directories(sys());
    }
    void TearDown() override { fs::remove_all(root_); }

    std::string dev() const { return (root_ / "dev").string(); }
    std::string sys() const { return (root_ / "sys").string(); }
    void node(const std::string& name) const { std::ofstream(dev() + "/" + name).put('\0'); }
    // A ttyS node with the 8250 driver's port type (0: no UART).
    void uart(const std::string& name, int type) const {
        node(name);
        fs::create_directories(sys() + "/class/tty/" + name);
        std::ofstream(sys() + "/class/tty/" + name + "/type") << type << "\n";
    }

    fs::path root_;
};

TEST_F(FakeTree, TheUsualKindsInOrderNumbersSortedAndAliasesFirst) {
    for (const char* name : {"ttyUSB10", "ttyUSB2", "ttyACM0", "ttyAMA0", "ttyTHS1", "tty0",
                             "tty12", "ttyUSBx", "ttyprintk", "console", "null"}) {
        node(name);
    }
    fs::create_symlink("ttyAMA0", dev() + "/serial0");
    const auto d = dev();
    EXPECT_EQ(serial_candidates(dev(), sys()),
              (std::vector<std::string>{d + "/serial0", d + "/ttyAMA0", d + "/ttyTHS1",
                                        d + "/ttyUSB2", d + "/ttyUSB10", d + "/ttyACM0"}));
}

TEST_F(FakeTree, OnlyTtySWithAUartBehindIt) {
    uart("ttyS0", 4);  // PORT_16550A
    for (int i = 1; i < 32; ++i) {
        uart("ttyS" + std::to_string(i), 0);  // a PC's empty ones
    }
    uart("ttyS4", 4);
    node("ttyS5");  // no sysfs entry: not listed
    EXPECT_EQ(serial_candidates(dev(), sys()),
              (std::vector<std::string>{dev() + "/ttyS0", dev() + "/ttyS4"}));
}

TEST_F(FakeTree, TheHintNamesWhatExistsAndWhatToDo) {
    EXPECT_EQ(candidates_hint({}),
              "no serial devices here (is the adapter plugged in? see `dmesg`)");
    EXPECT_EQ(candidates_hint({"/dev/ttyUSB0", "/dev/ttyAMA0"}),
              "serial devices here: /dev/ttyUSB0, /dev/ttyAMA0; set serial.device (or --device) "
              "to the gimbal's, or run `gportd --probe` to find it");
    EXPECT_TRUE(serial_candidates(dev() + "/missing", sys()).empty());
}

}  // namespace
}  // namespace gport::daemon
