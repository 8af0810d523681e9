// What every connection of gport-web shares (one io_context, one thread).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/address.hpp>
#include <string>
#include <vector>

#include "gateway.hpp"
#include "gport/web/login_codes.hpp"
#include "gport/web/options.hpp"
#include "gport/web/registry.hpp"
#include "gport/web/request_rates.hpp"
#include "gport/web/sessions.hpp"
#include "gport/web/tokens.hpp"
#include "served_addresses.hpp"

namespace gport::web {

struct Context {
    // `bound`: the port served (options.port may be 0: any free port).
    Context(boost::asio::io_context& context, Options opts, std::vector<Token> secrets,
            unsigned short bound)
        : io(context),
          options(std::move(opts)),
          port(bound),
          tokens(std::move(secrets)),
          served(listen_address(options.address)),
          gateway(context, options.socket, registry) {}

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
    // Every open connection: counted, fanned out to, closed at exit.
    Registry registry;
    Gateway gateway;
};

}  // namespace gport::web
