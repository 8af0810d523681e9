// What every connection of gport-web shares (one io_context, one thread).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "gateway.hpp"
#include "gport/web/login_codes.hpp"
#include "gport/web/options.hpp"
#include "gport/web/request_rates.hpp"
#include "gport/web/sessions.hpp"
#include "gport/web/tokens.hpp"
#include "hub.hpp"
#include "served_addresses.hpp"

namespace gport::web {

// The open connections (docs/web.md, "Limits"): all of them, those of each
// peer address, and those that have not yet shown a valid session or token,
// oldest first, each with how to close it.
struct Connections {
    std::size_t total = 0;
    std::map<std::string, std::size_t> per_address;
    std::map<std::uint64_t, std::function<void()>> unauthenticated;
    std::uint64_t next = 0;
};

// The key a peer is counted under: an IPv4 address, or an IPv6 address's
// /64 (one host may hold a whole /64); a v4-mapped address as IPv4.
std::string peer_key(const boost::asio::ip::address& address);

struct Context {
    // `bound`: the port served (options.port may be 0: any free port).
    Context(boost::asio::io_context& context, Options opts, std::vector<Token> secrets,
            unsigned short bound)
        : io(context),
          options(std::move(opts)),
          port(bound),
          tokens(std::move(secrets)),
          served(listen_address(options.address)),
          gateway(context, options.socket, hub) {}

    // The address to listen on (checked by parse_options; loopback if not).
    static boost::asio::ip::address listen_address(const std::string& text) {
        boost::system::error_code ec;
        const auto address = boost::asio::ip::make_address(text, ec);
        return ec ? boost::asio::ip::address(boost::asio::ip::address_v4::loopback()) : address;
    }

    boost::asio::io_context& io;
    Options options;
    const unsigned short port;  // the port served
    std::vector<Token> tokens;
    ServedAddresses served;  // the Host names accepted as IP literals
    Sessions sessions;
    LoginCodes codes;
    LoginGuard logins;
    RequestRates api_rates;
    Hub hub;
    Gateway gateway;
    Connections connections;
    // How to close each open connection (at exit: their operations end, so
    // io.run() returns with nothing pending).
    std::map<const void*, std::function<void()>> closers;
};

// Counts one connection for as long as it lives: in the total, under its
// peer's key, and among the unauthenticated ones until authenticated().
class ConnectionSlot {
  public:
    ConnectionSlot(Context& context, std::string peer);
    ~ConnectionSlot();
    ConnectionSlot(const ConnectionSlot&) = delete;
    ConnectionSlot& operator=(const ConnectionSlot&) = delete;

    const std::string& peer() const { return peer_; }
    bool authenticated() const { return authenticated_; }
    // How to close the connection when it is the oldest unauthenticated one
    // and a new connection needs its room.
    void on_evict(std::function<void()> close);
    // It showed a valid session or token: it leaves the unauthenticated ones.
    void authenticate();

  private:
    Context& context_;
    std::string peer_;
    std::uint64_t id_;
    bool authenticated_ = false;
};

}  // namespace gport::web
