#include "line_sim.hpp"

#include <boost/asio/post.hpp>
#include <cstdlib>
#include <future>

#include "posix.hpp"

namespace gport::bench {

LineSim::LineSim(unsigned baud, double rate_hz, const std::string& link) {
    sim::SimOptions options;
    options.baud = baud;
    options.model.stream_rate_hz = rate_hz;
    options.link_path = link;
    options.trace = [this](const std::string& line) { on_trace(line); };
    start_ns_ = now_ns();  // the simulator's clock starts as it is built, microseconds later
    sim_ = std::make_unique<sim::PtySimulator>(io_, std::move(options));
    device_ = sim_->device_path();
    thread_ = std::thread([this] { io_.run(); });
}

LineSim::~LineSim() {
    boost::asio::post(io_, [this] { sim_->stop(); });
    thread_.join();
}

std::int64_t LineSim::stop_time(std::uint64_t n) const {
    std::lock_guard lock(mutex_);
    return n < stop_times_.size() ? stop_times_[n] : -1;
}

std::uint64_t LineSim::backlog_max() {
    std::promise<std::uint64_t> result;
    boost::asio::post(io_, [&] { result.set_value(sim_->stats().read_backlog_max); });
    return result.get_future().get();
}

// {"t_ms":1234.5,"cmd":"0x85","mode":"speed","speed":[0,0,0],...}: the
// keys' order is fixed (docs/simulator.md, "Trace format").
void LineSim::on_trace(const std::string& line) {
    if (line.find(R"("cmd":"0x85","mode":"speed")") == std::string::npos) {
        return;
    }
    if (line.find(R"("speed":[0,0,0])") == std::string::npos) {
        ++speeds_;
        return;
    }
    const double t_ms = std::strtod(line.c_str() + line.find(':') + 1, nullptr);
    {
        std::lock_guard lock(mutex_);
        stop_times_.push_back(start_ns_ + static_cast<std::int64_t>(t_ms * 1e6));
    }
    ++stops_;
}

}  // namespace gport::bench
