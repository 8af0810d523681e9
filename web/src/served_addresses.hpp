// The addresses gport-web is reached at (docs/web.md, "Listening"): the
// one it listens on, or, listening on every address (0.0.0.0, ::), those of
// the machine's interfaces that are up. They make the links it prints (an
// http://0.0.0.0:PORT/ link opens nothing) and the Host names it accepts (an
// IP literal is a Host only when it is one of them: a request naming another
// address was not meant for this server).
#pragma once

#include <boost/asio/ip/address.hpp>
#include <chrono>
#include <vector>

namespace gport::web {

// The interfaces' addresses for an unspecified `listen` (IPv4 for 0.0.0.0;
// IPv6 and IPv4 for ::), else `listen` itself. Loopback ones last.
std::vector<boost::asio::ip::address> served_addresses(const boost::asio::ip::address& listen);

// served_addresses(), read again at most once a second (interfaces come and
// go: DHCP, a Wi-Fi access point started after gport-web).
class ServedAddresses {
  public:
    explicit ServedAddresses(boost::asio::ip::address listen) : listen_(std::move(listen)) {}
    // Whether `address` is one of them (a v4-mapped IPv6 address as IPv4).
    bool contains(const boost::asio::ip::address& address);
    // Whether one of them is a loopback address (so "localhost" names this server).
    bool has_loopback();

  private:
    const std::vector<boost::asio::ip::address>& current();

    boost::asio::ip::address listen_;
    std::vector<boost::asio::ip::address> addresses_;
    std::chrono::steady_clock::time_point read_at_{};
    bool read_ = false;
};

}  // namespace gport::web
