// The monitor's key parsing: letters, arrows in both encodings, partial
// escape sequences kept for the next read.
#include "keys.hpp"

#include <gtest/gtest.h>

namespace gport::cli::monitor {
namespace {

TEST(MonitorKeys, LettersAndArrows) {
    std::string bytes = "qc\x1b[A\x1b[B\x1b[C\x1b[DQx\x1bOC";
    const std::vector<Key> expected = {Key::kQuit,  Key::kCentre, Key::kUp,   Key::kDown,
                                       Key::kRight, Key::kLeft,   Key::kQuit, Key::kRight};
    EXPECT_EQ(take_keys(bytes), expected);
    EXPECT_EQ(bytes, "");
}

TEST(MonitorKeys, PartialSequenceWaitsForTheRest) {
    std::string bytes = "c\x1b[";
    EXPECT_EQ(take_keys(bytes), std::vector<Key>{Key::kCentre});
    EXPECT_EQ(bytes, "\x1b[");
    bytes += "D";
    EXPECT_EQ(take_keys(bytes), std::vector<Key>{Key::kLeft});
    EXPECT_EQ(bytes, "");
}

TEST(MonitorKeys, OtherSequencesAreDropped) {
    std::string bytes = "\x1b[1;5C\x1b[15~z";  // Ctrl-Right is still right; F5 nothing
    EXPECT_EQ(take_keys(bytes), std::vector<Key>{Key::kRight});
    EXPECT_EQ(bytes, "");
}

}  // namespace
}  // namespace gport::cli::monitor
