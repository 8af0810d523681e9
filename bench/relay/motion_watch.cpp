#include "motion_watch.hpp"

#include <chrono>
#include <stdexcept>

#include "../e2e/posix.hpp"

namespace gport::bench::relay {

MotionWatch::MotionWatch(const std::string& socket) {
    auto fd = connect_unix_retry(socket, 5000);
    if (!fd || !write_all(fd->get(), R"({"jsonrpc":"2.0","id":1,"method":"subscribe",)"
                                     R"("params":{"topics":["motion"]}})"
                                     "\n")) {
        throw std::runtime_error("gportd's socket " + socket + " does not answer");
    }
    thread_ = std::thread([this, fd = std::move(*fd)] {
        std::string pending;
        std::string line;
        while (!stop_) {
            if (!read_line(fd.get(), pending, line, 200)) {
                // A timeout (look at stop_ again) or gportd gone (do not spin).
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
                continue;
            }
            if (line.find(R"("reason":"lease_expired")") != std::string::npos) {
                ++lease_endings_;
            }
        }
    });
}

MotionWatch::~MotionWatch() {
    stop_ = true;
    thread_.join();
}

}  // namespace gport::bench::relay
