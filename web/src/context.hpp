// What every connection of gport-web shares (one io_context, one thread).
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstddef>
#include <functional>
#include <map>
#include <vector>

#include "gateway.hpp"
#include "gport/web/options.hpp"
#include "gport/web/sessions.hpp"
#include "gport/web/tokens.hpp"
#include "hub.hpp"

namespace gport::web {

struct Context {
    Context(boost::asio::io_context& context, Options opts, std::vector<Token> secrets)
        : io(context),
          options(std::move(opts)),
          tokens(std::move(secrets)),
          gateway(context, options.socket, hub) {}

    boost::asio::io_context& io;
    Options options;
    unsigned short port = 0;  // the port bound (options.port may be 0)
    std::vector<Token> tokens;
    Sessions sessions;
    LoginGuard logins;
    Hub hub;
    Gateway gateway;
    std::size_t connections = 0;
    // How to close each open connection (at exit: their operations end, so
    // io.run() returns with nothing pending).
    std::map<const void*, std::function<void()>> closers;
};

// Counts one connection for as long as it lives.
class ConnectionSlot {
  public:
    explicit ConnectionSlot(Context& context) : context_(context) { ++context_.connections; }
    ~ConnectionSlot() { --context_.connections; }
    ConnectionSlot(const ConnectionSlot&) = delete;
    ConnectionSlot& operator=(const ConnectionSlot&) = delete;

  private:
    Context& context_;
};

}  // namespace gport::web
