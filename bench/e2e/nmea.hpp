// The NMEA side of the comparison with gpsd: the sentence the feeder writes
// for fix n, and how a gpsd TPV report gives n back.
//
// Fix n carries the UTC time n × 10 ms after midnight (hhmmss.ss, the
// resolution of NMEA time), so gpsd's TPV "time" field names the fix it came
// from, as roll and pitch do for gportd's attitude lines (fake_gimbal.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace gport::bench {

// "$GPRMC,...*CS\r\n" for fix n: one sentence per fix, the least work a GPS
// can ask of gpsd (a receiver that also sends GGA, GSA, GSV costs it more).
std::string nmea_for(std::uint32_t n);

// The fix number a gpsd line carries: from the "time" of a TPV report; 0 for
// any other line (VERSION, DEVICES, WATCH) or a TPV without time.
std::uint32_t counter_of_gpsd_line(std::string_view line);

}  // namespace gport::bench
