// speed --for's progress: elapsed time and the gimbal's hall angles, one
// line updated in place on a terminal, plain lines otherwise, then how the
// motion ended.
#pragma once

#include <chrono>
#include <nlohmann/json.hpp>
#include <ostream>

namespace gport::cli {

class Progress {
  public:
    Progress(std::ostream& out, std::chrono::milliseconds total, bool in_place);

    // An attitude notification's params.
    void show(const nlohmann::json& attitude);
    // A motion notification's params (ended or replaced); `quiet` only
    // finishes the line (interrupted, --json).
    void end(const nlohmann::json& motion, bool quiet);

  private:
    std::ostream& out_;
    std::chrono::milliseconds total_;
    bool in_place_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace gport::cli
