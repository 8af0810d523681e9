// Recordings of the byte stream between the simulator and its client.
//
// A text file, one write or read per line:
//
//   # gport-sim recording v1
//   <t_us> <rx|tx> <hex bytes>
//
// t_us is microseconds since the simulator started (decimal, non-decreasing);
// rx is what the gimbal received from the client, tx what it sent (after
// fault injection, exactly as written to the pty); hex is lowercase, two
// digits a byte, no separators. Lines starting with '#' and blank lines are
// ignored.
#pragma once

#include <cstdint>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gport/protocol/result.hpp"
#include "gport/sim/model.hpp"

namespace gport::sim {

enum class Direction { kRx, kTx };

struct RecordEntry {
    Duration t{0};
    Direction direction = Direction::kTx;
    std::vector<std::uint8_t> bytes;
    friend bool operator==(const RecordEntry&, const RecordEntry&) = default;
};

std::string format_record_line(const RecordEntry& entry);
// Parses one non-comment line; the error says what is wrong with it.
protocol::Result<RecordEntry> parse_record_line(std::string_view line);

// Loads a whole recording; errors name the file and the line number.
protocol::Result<std::vector<RecordEntry>> load_recording(const std::string& path);

class Recorder {
  public:
    // Creates (truncates) the file; throws std::runtime_error naming it.
    explicit Recorder(const std::string& path);
    // Appends one line and flushes it, so a killed simulator leaves a usable file.
    void write(Duration t, Direction direction, std::span<const std::uint8_t> bytes);

  private:
    std::string path_;
    std::ofstream out_;
};

}  // namespace gport::sim
