// The soak's line-rate attacks (issue 30), run while scripts/soak.sh's
// gport-sim drains the line at 115200 baud: in turn, for a window each,
//   (h) 8 connections flooding `photo` with 1 KiB metas,
//   (i) 32 read-only connections calling `captures` (limit 1000),
//   (j) one read-only connection sending batches of 32 `captures` (800),
// each from a process of its own (line_flood.hpp) that reconnects when gportd
// closes it. What they do to the stop and to attitude shows in the soak's
// burst and subscriber checks; what they do to memory in its RSS check.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "line_flood.hpp"

namespace gport::bench {

struct LineRateAttackOptions {
    std::string socket;
    uid_t reader_uid = 0;  // the read-only floods' uid (0: ours)
    int window_ms = 4000;  // how long each flood runs
    int pause_ms = 2000;   // quiet between two
};

class LineRateAttacks {
  public:
    explicit LineRateAttacks(LineRateAttackOptions o) : o_(std::move(o)) {}
    // Starts and ends the windows as time passes.
    void act(std::int64_t t_ns);
    void finish();

    std::vector<std::string> problems() const { return problems_; }
    nlohmann::json figures() const;

  private:
    void begin(std::int64_t t_ns);

    LineRateAttackOptions o_;
    std::unique_ptr<FloodProcess> running_;
    std::size_t next_ = 0;
    std::int64_t next_change_ns_ = 0;
    std::map<std::string, std::uint64_t> windows_;
    std::vector<std::string> problems_;
};

}  // namespace gport::bench
