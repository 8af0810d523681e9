// Logs attitude samples as CSV with timestamps:
//   seq,time,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw
// `time` is the daemon's receive time in seconds since the epoch.
//
//     attitude_csv [SOCKET [SAMPLES [RATE_HZ]]]   (default: $GPORT_SOCKET, 50, 10 Hz)
#include <cstdlib>
#include <gport/client/client.hpp>
#include <iomanip>
#include <iostream>

namespace gc = gport::client;
using namespace std::chrono_literals;

int main(int argc, char** argv) {
    const long samples = argc > 2 ? std::atol(argv[2]) : 50;
    const double rate = argc > 3 ? std::atof(argv[3]) : 10;
    try {
        auto gimbal = gc::Client::connect(argc > 1 ? argv[1] : gc::Client::default_socket());
        gimbal.subscribe({"attitude"}, rate);
        std::cout << "seq,time,imu_roll,imu_pitch,imu_yaw,hall_roll,hall_pitch,hall_yaw\n"
                  << std::fixed;
        for (long written = 0; written < samples;) {
            const auto n = gimbal.next_notification(5s);
            if (!n) {
                std::cerr << "attitude_csv: no attitude for 5 s (is the gimbal connected?)\n";
                return 1;
            }
            if (const auto* s = std::get_if<gc::AttitudeSample>(&*n)) {
                std::cout << s->seq << ',' << std::setprecision(6) << s->time << ','
                          << std::setprecision(2) << s->imu.roll << ',' << s->imu.pitch << ','
                          << s->imu.yaw << ',' << s->hall.roll << ',' << s->hall.pitch << ','
                          << s->hall.yaw << '\n';
                ++written;
            }
        }
        std::cout.flush();
        return 0;
    } catch (const gc::Error& e) {
        std::cerr << "attitude_csv: " << e.what() << "\n";
        return e.transport() ? 69 : 1;
    }
}
