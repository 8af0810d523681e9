#include "soak_line_rate.hpp"

#include <array>
#include <stdexcept>

namespace gport::bench {
namespace {

struct Window {
    FloodKind kind;
    int connections;
    bool read_only;
};

constexpr std::array<Window, 3> kWindows = {{
    {FloodKind::kPhoto, 8, false},
    {FloodKind::kCaptures, 32, true},
    {FloodKind::kBatches, 1, true},
}};

}  // namespace

void LineRateAttacks::act(std::int64_t t_ns) {
    if (next_change_ns_ == 0) {
        next_change_ns_ = t_ns + std::int64_t{o_.pause_ms} * 1'000'000;
    }
    if (t_ns < next_change_ns_) {
        return;
    }
    if (running_) {
        running_.reset();  // kills the flood
        next_change_ns_ = t_ns + std::int64_t{o_.pause_ms} * 1'000'000;
        return;
    }
    begin(t_ns);
}

void LineRateAttacks::begin(std::int64_t t_ns) {
    const auto& w = kWindows[next_++ % kWindows.size()];
    next_change_ns_ = t_ns + std::int64_t{o_.window_ms} * 1'000'000;
    try {
        running_ = std::make_unique<FloodProcess>(o_.socket, w.kind, w.connections,
                                                  w.read_only ? o_.reader_uid : 0);
        ++windows_[to_string(w.kind)];
    } catch (const std::exception& e) {
        if (problems_.size() < 10) {
            problems_.push_back(std::string("line-rate flood did not start: ") + e.what());
        }
    }
}

void LineRateAttacks::finish() {
    running_.reset();
}

nlohmann::json LineRateAttacks::figures() const {
    return {{"windows", windows_},
            {"window_ms", o_.window_ms},
            {"pause_ms", o_.pause_ms},
            {"reader_uid", o_.reader_uid}};
}

}  // namespace gport::bench
