// A UTC instant as a calendar date and time of day, and back, on 64-bit
// counts whatever the C library's time_t: on Debian 12's armhf time_t is
// 32 bits, and gmtime_r() and timegm() end at 2038-01-19, while the
// captures' UTC (the autopilot's) is taken up to 2100 and a captures file
// may hold any int64. Used by the client library's CSV and GeoJSON and by
// gportctl geotag's EXIF tags. The proleptic Gregorian calendar, after
// Howard Hinnant's days_from_civil and civil_from_days
// (https://howardhinnant.github.io/date_algorithms.html).
#pragma once

#include <cstdint>
#include <optional>

namespace gport::base {

struct CivilTime {
    std::int64_t year = 1970;
    unsigned month = 1;  // 1 to 12
    unsigned day = 1;    // 1 to 31
    unsigned hour = 0;
    unsigned minute = 0;
    unsigned second = 0;
    std::int64_t micros = 0;  // 0 to 999999
};

// Days since 1970-01-01 of a date (any year int64's days reach).
constexpr std::int64_t days_from_civil(std::int64_t year, unsigned month, unsigned day) {
    year -= month <= 2 ? 1 : 0;
    const std::int64_t era = (year >= 0 ? year : year - 399) / 400;
    const auto year_of_era = static_cast<unsigned>(year - era * 400);  // 0 to 399
    const unsigned day_of_year = (153 * (month > 2 ? month - 3 : month + 9) + 2) / 5 + day - 1;
    const unsigned day_of_era =
        year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;  // 0 to 146096
    return era * 146097 + static_cast<std::int64_t>(day_of_era) - 719468;
}

// The calendar time of `utc_us` microseconds since the epoch, over the
// whole int64 range (before 1970 too).
constexpr CivilTime civil_time(std::int64_t utc_us) {
    constexpr std::int64_t kMicrosPerDay = 86400LL * 1000000;
    std::int64_t days = utc_us / kMicrosPerDay;
    std::int64_t of_day = utc_us % kMicrosPerDay;  // no days * kMicrosPerDay: it can overflow
    if (of_day < 0) {
        of_day += kMicrosPerDay;
        days -= 1;
    }
    const std::int64_t z = days + 719468;
    const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const auto day_of_era = static_cast<unsigned>(z - era * 146097);  // 0 to 146096
    const unsigned year_of_era =
        (day_of_era - day_of_era / 1460 + day_of_era / 36524 - day_of_era / 146096) / 365;
    const unsigned day_of_year =
        day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
    const unsigned shifted_month = (5 * day_of_year + 2) / 153;  // 0 (March) to 11
    CivilTime t;
    t.day = day_of_year - (153 * shifted_month + 2) / 5 + 1;
    t.month = shifted_month < 10 ? shifted_month + 3 : shifted_month - 9;
    t.year = static_cast<std::int64_t>(year_of_era) + era * 400 + (t.month <= 2 ? 1 : 0);
    const auto seconds = static_cast<unsigned>(of_day / 1000000);
    t.hour = seconds / 3600;
    t.minute = seconds / 60 % 60;
    t.second = seconds % 60;
    t.micros = of_day % 1000000;
    return t;
}

// The seconds since the epoch of a date and time of day taken as UTC; none
// for a date no calendar has (2026-02-30). The time of day is added as it
// is (23:59:60, a leap second, is the next day's first second).
constexpr std::optional<std::int64_t> epoch_seconds(std::int64_t year, unsigned month, unsigned day,
                                                    unsigned hour, unsigned minute,
                                                    unsigned second) {
    constexpr unsigned kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    const bool leap = year % 4 == 0 && (year % 100 != 0 || year % 400 == 0);
    if (month < 1 || month > 12 || day < 1 ||
        day > kDays[month - 1] + (month == 2 && leap ? 1 : 0)) {
        return std::nullopt;
    }
    return days_from_civil(year, month, day) * 86400 + hour * std::int64_t{3600} +
           minute * std::int64_t{60} + second;
}

static_assert(days_from_civil(1970, 1, 1) == 0);
static_assert(days_from_civil(2000, 3, 1) == 11017);
static_assert(civil_time(0).year == 1970 && civil_time(-1).year == 1969);
static_assert(civil_time(-1).micros == 999999 && civil_time(-1).second == 59);

}  // namespace gport::base
