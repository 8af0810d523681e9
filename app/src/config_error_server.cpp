#include "gport/app/config_error_server.hpp"

#include <fmt/format.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>
#include <csignal>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "gport/config/loader.hpp"
#include "gport/ipc/json_rpc.hpp"
#include "gport/systemd/activation.hpp"
#include "gport/systemd/notifier.hpp"
#include "gport/systemd/watchdog.hpp"

namespace gport::app {
namespace {

namespace asio = boost::asio;
using Local = asio::local::stream_protocol;
using Limits = ConfigErrorServing;
using nlohmann::json;

// The loader's text (one or more lines) as one line.
std::string one_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
        text.pop_back();
    }
    std::string out;
    for (const char c : text) {
        out += c == '\n' ? std::string("; ") : std::string(1, c);
    }
    return out;
}

std::string client_message(const std::string& problem) {
    return fmt::format(
        "gportd's configuration is invalid, so it serves nothing: {}. Fix the file, then "
        "`systemctl restart gportd` (or `systemctl reload gportd`)",
        one_line(problem));
}

// To the journal (stderr under systemd), at the priority of its <N> prefix.
void log_line(int priority, const std::string& text) {
    std::fprintf(stderr, "<%d>gportd: %s\n", priority, text.c_str());
    std::fflush(stderr);
}

// -32006 with the request's id: null when the line is not an object with a
// string or number id. Only the top level is kept while parsing, so no line
// makes a large document.
std::string reply_to(std::string_view line, const std::string& message) {
    json id = nullptr;
    const auto top_level_only = [](int depth, json::parse_event_t, json&) { return depth <= 1; };
    const auto request = json::parse(line, top_level_only, false);
    if (request.is_object()) {
        const auto it = request.find("id");
        if (it != request.end() && (it->is_string() || it->is_number())) {
            id = *it;
        }
    }
    const json error{{"code", ipc::rpc_error::kConfigInvalid}, {"message", message}};
    return json{{"jsonrpc", "2.0"}, {"id", id}, {"error", error}}.dump() + "\n";
}

struct Shared {
    std::string message;
    std::size_t open = 0;
};

// One client: its first line (or what came before EOF, or nothing within
// kReadTimeout) gets the error; then the connection is closed.
class Connection : public std::enable_shared_from_this<Connection> {
  public:
    Connection(Local::socket socket, std::shared_ptr<Shared> shared)
        : socket_(std::move(socket)), timer_(socket_.get_executor()), shared_(std::move(shared)) {
        ++shared_->open;
    }
    ~Connection() { --shared_->open; }
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    void start() {
        timer_.expires_after(Limits::kReadTimeout);
        timer_.async_wait([self = shared_from_this()](const boost::system::error_code& ec) {
            if (!ec) {
                boost::system::error_code ignored;
                self->socket_.close(ignored);
            }
        });
        asio::async_read_until(socket_, asio::dynamic_buffer(buffer_, Limits::kMaxLine), '\n',
                               [self = shared_from_this()](const boost::system::error_code& ec,
                                                           std::size_t n) { self->answer(ec, n); });
    }

  private:
    void answer(const boost::system::error_code& ec, std::size_t n) {
        const bool line = !ec;
        const bool too_long = ec == asio::error::not_found;
        const bool partial = ec == asio::error::eof && !buffer_.empty();
        if (!line && !too_long && !partial) {
            timer_.cancel();
            return;  // gone, or silent until the timeout
        }
        reply_ = reply_to(too_long ? std::string_view() : std::string_view(buffer_).substr(0, n),
                          shared_->message);
        asio::async_write(
            socket_, asio::buffer(reply_),
            [self = shared_from_this()](const boost::system::error_code&, std::size_t) {
                self->timer_.cancel();
                boost::system::error_code ignored;
                self->socket_.shutdown(Local::socket::shutdown_both, ignored);
                self->socket_.close(ignored);
            });
    }

    Local::socket socket_;
    asio::steady_timer timer_;
    std::shared_ptr<Shared> shared_;
    std::string buffer_;
    std::string reply_;
};

class Server {
  public:
    Server(int fd, const std::string& problem, const config::CommandLine& command_line)
        : acceptor_(io_),
          signals_(io_, SIGTERM, SIGINT, SIGHUP),
          watchdog_(io_, notifier_),
          command_line_(command_line),
          shared_(std::make_shared<Shared>()) {
        acceptor_.assign(Local(), fd);
        set_problem(problem);
    }

    int run() {
        accept();
        wait_signal();
        watchdog_.start();
        notifier_.ready();
        io_.run();
        return status_;
    }

  private:
    void set_problem(const std::string& problem) {
        shared_->message = client_message(problem);
        log_line(3, "configuration error: " + one_line(problem) +
                        "; serving only this error on the socket systemd passed (-32006) until "
                        "the file is fixed and the service restarted or reloaded");
        notifier_.status("configuration error: " + one_line(problem));
    }

    void accept() {
        acceptor_.async_accept([this](const boost::system::error_code& ec, Local::socket socket) {
            if (ec == asio::error::operation_aborted) {
                return;
            }
            if (!ec && shared_->open < Limits::kMaxConnections) {
                std::make_shared<Connection>(std::move(socket), shared_)->start();
            }
            accept();  // a refused or failed one is closed as `socket` goes
        });
    }

    void wait_signal() {
        signals_.async_wait([this](const boost::system::error_code& ec, int signal) {
            if (ec) {
                return;
            }
            if (signal == SIGHUP) {
                reload();
            } else {
                notifier_.stopping();
                stop(0);
            }
        });
    }

    void reload() {
        notifier_.reloading();
        const auto config = config::load_config(command_line_);
        if (config) {
            log_line(5, fmt::format("the configuration loads now; exiting {} so that systemd "
                                    "starts gportd with it",
                                    Limits::kExitConfigFixed));
            notifier_.stopping();
            stop(Limits::kExitConfigFixed);
            return;
        }
        set_problem(config.error().text());
        notifier_.ready();
        wait_signal();
    }

    void stop(int status) {
        status_ = status;
        boost::system::error_code ignored;
        acceptor_.close(ignored);
        watchdog_.stop();
        io_.stop();
    }

    asio::io_context io_;
    Local::acceptor acceptor_;
    asio::signal_set signals_;
    systemd::Notifier notifier_;
    systemd::WatchdogDriver watchdog_;
    const config::CommandLine& command_line_;
    std::shared_ptr<Shared> shared_;
    int status_ = 0;
};

}  // namespace

std::optional<int> serve_config_error_if_activated(const std::string& problem,
                                                   const config::CommandLine& command_line) {
    std::optional<int> fd;
    try {
        fd = systemd::activated_socket_fd();
    } catch (const systemd::ActivationError& e) {
        log_line(3, std::string("socket activation: ") + e.what());
        return config::kExitConfig;
    }
    if (!fd) {
        return std::nullopt;
    }
    try {
        return Server(*fd, problem, command_line).run();
    } catch (const std::exception& e) {
        log_line(3, std::string("cannot serve the configuration error: ") + e.what());
        return config::kExitConfig;
    }
}

}  // namespace gport::app
