// A program outside the tree, built against the installed libgport-client:
// with no gportd at the given path it must get a transport Error.
#include <gport/client/client.hpp>
#include <iostream>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::cerr << "usage: consumer SOCKET\n";
        return 64;
    }
    try {
        gport::client::Client::connect(argv[1]).status();
    } catch (const gport::client::Error& e) {
        if (e.transport()) {
            std::cout << "ok: " << e.what() << "\n";
            return 0;
        }
        std::cerr << "unexpected error: " << e.what() << "\n";
    }
    return 1;
}
