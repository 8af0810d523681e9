// Sweep and photo: point the camera at a few yaw positions, wait until it
// is there, take a photo at each, then centre.
//
//     sweep_and_photo [SOCKET]      (default: $GPORT_SOCKET or /run/gportd.sock)
#include <gport/client/client.hpp>
#include <iostream>

namespace gc = gport::client;

int main(int argc, char** argv) {
    try {
        auto gimbal = gc::Client::connect(argc > 1 ? argv[1] : gc::Client::default_socket());
        for (const double yaw : {-30.0, 0.0, 30.0}) {
            const auto moved = gimbal.angle({.pitch = -10, .yaw = yaw}, {.wait = true});
            const auto& end = moved.ended;
            std::cout << "yaw " << yaw << ": " << (end ? end->reason : "sent");
            if (end && end->attitude) {
                std::cout << " at yaw " << end->attitude->hall.yaw << " after " << end->elapsed_ms
                          << " ms";
            }
            std::cout << "\n";
            if (end && end->reason != "reached") {
                std::cerr << "sweep_and_photo: the gimbal did not reach yaw " << yaw << "\n";
                return 1;
            }
            gimbal.photo();
            std::cout << "photo at yaw " << yaw << std::endl;
        }
        gimbal.center({.wait = true});
        std::cout << "centred" << std::endl;
        return 0;
    } catch (const gc::Error& e) {
        std::cerr << "sweep_and_photo: " << e.what() << "\n";
        return e.transport() ? 69 : 1;
    }
}
