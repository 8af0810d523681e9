// Accepts connections: each becomes an HttpSession, or, beyond the limits
// of the registry (gport/web/registry.hpp), gets 503 and is closed.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <memory>
#include <string>

#include "context.hpp"

namespace gport::web {

// A socket bound to `endpoint` and listening; throws
// boost::system::system_error when it cannot. (Bound before the Context is
// built, which needs the port served.)
boost::asio::ip::tcp::acceptor listen_on(boost::asio::io_context& io,
                                         const boost::asio::ip::tcp::endpoint& endpoint);

class Acceptor : public std::enable_shared_from_this<Acceptor> {
  public:
    Acceptor(Context& context, boost::asio::ip::tcp::acceptor listening)
        : context_(context), acceptor_(std::move(listening)) {}
    boost::asio::ip::tcp::endpoint local() const { return acceptor_.local_endpoint(); }
    void start() { accept(); }
    void stop() {
        boost::system::error_code ignored;
        acceptor_.close(ignored);
    }

  private:
    void accept();
    void admit(boost::asio::ip::tcp::socket socket);
    void turn_away(boost::asio::ip::tcp::socket socket, const std::string& message);

    Context& context_;
    boost::asio::ip::tcp::acceptor acceptor_;
};

}  // namespace gport::web
