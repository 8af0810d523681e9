// Issue 30, item 3: positions for geotags only from the vehicle's autopilot
// (compid 1) and within bounds (position.hpp). The values seen in the
// field first: INT32_MAX latitude, INT32_MIN altitude.
#include <gtest/gtest.h>

#include <limits>

#include "gport/mavlink/bridge/position.hpp"

namespace gport::mavlink::bridge {
namespace {

constexpr Header kAutopilot{0, 1, 1};

GlobalPositionInt zurich() {
    GlobalPositionInt p;
    p.lat = 473'769'000;
    p.lon = 85'417'000;
    p.alt = 408'000;
    p.relative_alt = 30'000;
    return p;
}

TEST(Position, TheFieldsValuesAreDroppedNamingTheValue) {
    auto p = zurich();
    p.lat = std::numeric_limits<std::int32_t>::max();
    const auto lat = position_problem(kAutopilot, p);
    ASSERT_TRUE(lat);
    EXPECT_NE(lat->find("lat 214.7483647 is outside -90..90"), std::string::npos) << *lat;
    p = zurich();
    p.alt = std::numeric_limits<std::int32_t>::min();
    const auto alt = position_problem(kAutopilot, p);
    ASSERT_TRUE(alt);
    EXPECT_NE(alt->find("alt_m -2147483.648 is outside -1000..20000 m AMSL"), std::string::npos)
        << *alt;
}

TEST(Position, EachBoundIsChecked) {
    const auto refused = [](auto change) {
        auto p = zurich();
        change(p);
        return position_problem(kAutopilot, p).has_value();
    };
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.lat = -900'000'001; }));
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.lon = 1'800'000'001; }));
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.lon = -1'800'000'001; }));
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.alt = -1'000'001; }));
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.alt = 20'000'001; }));
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.relative_alt = 21'000'001; }));
    EXPECT_TRUE(refused([](GlobalPositionInt& p) { p.relative_alt = -21'000'001; }));
    // The bounds themselves are positions.
    EXPECT_FALSE(refused([](GlobalPositionInt& p) {
        p.lat = -900'000'000;
        p.lon = 1'800'000'000;
        p.alt = 20'000'000;
        p.relative_alt = -21'000'000;
    }));
    EXPECT_FALSE(refused([](GlobalPositionInt& p) {
        p.lat = 900'000'000;
        p.lon = -1'800'000'000;
        p.alt = -1'000'000;
    }));
}

TEST(Position, OnlyTheAutopilotsComponentIsTaken) {
    for (std::uint8_t compid : {0, 2, 100, 154, 191, 250}) {
        const auto problem = position_problem(Header{0, 1, compid}, zurich());
        ASSERT_TRUE(problem) << int(compid);
        EXPECT_NE(problem->find("is not the vehicle's autopilot (component 1"), std::string::npos);
    }
    EXPECT_FALSE(position_problem(kAutopilot, zurich()));
}

}  // namespace
}  // namespace gport::mavlink::bridge
