// civil_time() and epoch_seconds(): UTC dates on 64-bit counts, also where
// the C library's time_t is 32 bits (this suite runs on armhf, where
// gmtime_r() ends at 2038-01-19T03:14:07Z).
#include "gport/base/civil_time.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <tuple>

namespace gport::base {
namespace {

auto fields(const CivilTime& t) {
    return std::tuple(t.year, t.month, t.day, t.hour, t.minute, t.second, t.micros);
}

TEST(CivilTime, DatesAroundTheEpochAnd2038) {
    EXPECT_EQ(fields(civil_time(0)), std::tuple(1970, 1U, 1U, 0U, 0U, 0U, 0));
    EXPECT_EQ(fields(civil_time(1795563183085470)),
              std::tuple(2026, 11U, 24U, 23U, 33U, 3U, 85470));
    // One second past a 32-bit time_t's end, and 2100 (the last year a
    // capture's UTC may have).
    EXPECT_EQ(fields(civil_time(2147483648LL * 1000000)),
              std::tuple(2038, 1U, 19U, 3U, 14U, 8U, 0));
    EXPECT_EQ(fields(civil_time(4102444799999999)),
              std::tuple(2099, 12U, 31U, 23U, 59U, 59U, 999999));
    EXPECT_EQ(fields(civil_time(-1)), std::tuple(1969, 12U, 31U, 23U, 59U, 59U, 999999));
    EXPECT_EQ(fields(civil_time(951782400LL * 1000000)), std::tuple(2000, 2U, 29U, 0U, 0U, 0U, 0))
        << "2000 is a leap year";
}

TEST(CivilTime, TheEndsOfInt64DoNotOverflow) {
    EXPECT_EQ(fields(civil_time(std::numeric_limits<std::int64_t>::max())),
              std::tuple(294247, 1U, 10U, 4U, 0U, 54U, 775807));
    EXPECT_EQ(fields(civil_time(std::numeric_limits<std::int64_t>::min())),
              std::tuple(-290308, 12U, 21U, 19U, 59U, 5U, 224192));
}

TEST(EpochSeconds, RoundTripsAndRefusesDatesNoCalendarHas) {
    EXPECT_EQ(epoch_seconds(1970, 1, 1, 0, 0, 0), 0);
    EXPECT_EQ(epoch_seconds(2038, 1, 19, 3, 14, 8), 2147483648LL);
    EXPECT_EQ(epoch_seconds(2024, 2, 29, 12, 0, 0), 1709208000LL);
    EXPECT_EQ(epoch_seconds(2016, 12, 31, 23, 59, 60), epoch_seconds(2017, 1, 1, 0, 0, 0))
        << "a leap second is the next day's first";
    EXPECT_FALSE(epoch_seconds(2026, 2, 29, 0, 0, 0)) << "2026 is no leap year";
    EXPECT_FALSE(epoch_seconds(1900, 2, 29, 0, 0, 0)) << "nor is 1900";
    EXPECT_FALSE(epoch_seconds(2026, 4, 31, 0, 0, 0));
    EXPECT_FALSE(epoch_seconds(2026, 13, 1, 0, 0, 0));
    EXPECT_FALSE(epoch_seconds(2026, 0, 1, 0, 0, 0));
    EXPECT_FALSE(epoch_seconds(2026, 1, 0, 0, 0, 0));
    for (std::int64_t s = -400LL * 366 * 86400; s < 400LL * 366 * 86400; s += 86400 * 7 + 3661) {
        const auto t = civil_time(s * 1000000);
        ASSERT_EQ(epoch_seconds(t.year, t.month, t.day, t.hour, t.minute, t.second), s);
    }
}

}  // namespace
}  // namespace gport::base
