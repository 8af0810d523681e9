// Accepts connections: each becomes an HttpSession, or, beyond the limits
// of connections.hpp, gets 503 and is closed.
#pragma once

#include <boost/asio/ip/tcp.hpp>
#include <memory>
#include <string>

#include "context.hpp"

namespace gport::web {

class Acceptor : public std::enable_shared_from_this<Acceptor> {
  public:
    // Binds; throws boost::system::system_error when it cannot.
    Acceptor(Context& context, const boost::asio::ip::tcp::endpoint& endpoint);
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
