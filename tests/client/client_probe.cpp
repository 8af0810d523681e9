// A one-call client for the access tests, run as another user (setpriv):
// `client_probe SOCKET METHOD` prints "ok" or the error code.
#include <iostream>
#include <string>

#include "gport/client/client.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: client_probe SOCKET status|center\n";
        return 64;
    }
    const std::string method = argv[2];
    try {
        auto client = gport::client::Client::connect(argv[1]);
        if (method == "status") {
            client.status();
        } else if (method == "center") {
            client.center();
        } else {
            std::cerr << "client_probe: unknown method " << method << "; use status or center\n";
            return 64;
        }
        std::cout << "ok" << std::endl;
    } catch (const gport::client::Error& e) {
        std::cout << e.code() << std::endl;
    }
    return 0;
}
