// The asynchronous interface from the installed headers: compiles and links
// with Boost.Asio found through find_package(gport-client).
#include <boost/asio/io_context.hpp>
#include <gport/client/async_client.hpp>
#include <iostream>

int main(int argc, char** argv) {
    if (argc != 2) {
        return 64;
    }
    boost::asio::io_context io;
    gport::client::AsyncClient client(io);
    int status = 1;
    client.async_connect(argv[1], [&](std::optional<gport::client::Error> error) {
        status = error && error->transport() ? 0 : 1;
    });
    io.run();
    std::cout << (status == 0 ? "ok: async\n" : "unexpected\n");
    return status;
}
