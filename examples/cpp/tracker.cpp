// A tracker loop: steers yaw towards a moving target by streaming `speed`
// at 20 Hz with a 300 ms lease, reading the attitude from a subscription.
// If this program hangs, gportd stops the gimbal when the lease runs out;
// if it exits, when the connection closes.
//
//     tracker [SOCKET [SECONDS]]    (default: $GPORT_SOCKET, 5 s)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <gport/client/client.hpp>
#include <iostream>
#include <thread>

namespace gc = gport::client;
using namespace std::chrono_literals;

namespace {

constexpr auto kPeriod = 50ms;  // 20 Hz
constexpr auto kLease = 300ms;  // a few periods: the deadman if we hang
constexpr double kGain = 2.0;   // °/s per degree of error
constexpr double kMaxSpeed = 60;

// Where the "target" is at time t: a slow yaw oscillation.
double target_yaw(double seconds) {
    return 20 * std::sin(seconds * 0.8);
}

}  // namespace

int main(int argc, char** argv) {
    const double run_for = argc > 2 ? std::atof(argv[2]) : 5.0;
    try {
        auto gimbal = gc::Client::connect(argc > 1 ? argv[1] : gc::Client::default_socket());
        gimbal.subscribe({"attitude"}, 20);
        double yaw = gimbal.attitude().hall.yaw;
        const auto start = std::chrono::steady_clock::now();
        auto next = start;
        int commands = 0;
        while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(run_for)) {
            // Take the newest sample that arrived since the last command.
            while (auto n = gimbal.next_notification(0ms)) {
                if (const auto* sample = std::get_if<gc::AttitudeSample>(&*n)) {
                    yaw = sample->hall.yaw;
                }
            }
            const double t =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const double error = target_yaw(t) - yaw;
            const double rate = std::clamp(kGain * error, -kMaxSpeed, kMaxSpeed);
            gimbal.speed({.yaw = rate}, {.duration = 2s, .lease = kLease, .clamp = true});
            ++commands;
            next += kPeriod;
            std::this_thread::sleep_until(next);
        }
        gimbal.stop();
        std::cout << "sent " << commands << " speed commands; last yaw " << yaw << "\n";
        return 0;
    } catch (const gc::Error& e) {
        std::cerr << "tracker: " << e.what() << "\n";
        return e.transport() ? 69 : 1;
    }
}
