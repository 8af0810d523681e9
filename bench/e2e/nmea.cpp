#include "nmea.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace gport::bench {
namespace {

std::string with_checksum(std::string_view body) {
    std::uint8_t sum = 0;
    for (const char c : body) {
        sum ^= static_cast<std::uint8_t>(c);
    }
    return fmt::format("${}*{:02X}\r\n", body, sum);
}

// Parses the digits of `text` from `at` up to a non-digit; -1 when there are none.
double number_at(std::string_view text, std::size_t at) {
    double value = -1;
    if (at < text.size()) {
        std::from_chars(text.data() + at, text.data() + text.size(), value);
    }
    return value;
}

}  // namespace

std::string nmea_for(std::uint32_t n) {
    const std::uint32_t centis = n % 8'640'000;  // a day of 10 ms steps
    const auto seconds = centis / 100;
    const auto time = fmt::format("{:02}{:02}{:02}.{:02}", seconds / 3600, seconds / 60 % 60,
                                  seconds % 60, centis % 100);
    return with_checksum("GPRMC," + time + ",A,4807.038,N,01131.000,E,022.4,084.4,231126,003.1,W");
}

std::uint32_t counter_of_gpsd_line(std::string_view line) {
    if (line.find("\"class\":\"TPV\"") == std::string_view::npos) {
        return 0;
    }
    const auto key = line.find("\"time\":\"");
    if (key == std::string_view::npos) {
        return 0;
    }
    const auto t = line.find('T', key + 8);  // "2026-11-23T00:00:01.230Z"
    if (t == std::string_view::npos || t + 9 > line.size()) {
        return 0;
    }
    const double hours = number_at(line, t + 1);
    const double minutes = number_at(line, t + 4);
    const double seconds = number_at(line, t + 7);
    if (hours < 0 || minutes < 0 || seconds < 0) {
        return 0;
    }
    return static_cast<std::uint32_t>(std::lround(((hours * 60 + minutes) * 60 + seconds) * 100));
}

}  // namespace gport::bench
