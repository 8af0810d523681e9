// A capture log sink that keeps the lines it is given and reports the stats
// a test sets (CaptureLog's tests, and the captures method's through the
// dispatcher).
#pragma once

#include <string>
#include <vector>

#include "gport/capture/capture_log.hpp"

namespace gport::testing {

class FakeSink final : public capture::CaptureSink {
  public:
    void write(std::string line) override { lines.push_back(std::move(line)); }
    Stats stats() const override { return stats_value; }
    std::string path() const override { return "/var/lib/gportd/captures.jsonl"; }
    std::vector<std::string> lines;
    Stats stats_value;
};

}  // namespace gport::testing
