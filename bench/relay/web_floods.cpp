#include "web_floods.hpp"

#include <fmt/format.h>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <optional>

namespace gport::bench::relay {
namespace {

using Stopping = std::shared_ptr<std::atomic<bool>>;
constexpr int kPeersPerAddress = 14;  // under gport-web's 16 per address
constexpr auto kReconnectDelay = std::chrono::milliseconds(100);
constexpr auto kConnectStagger = std::chrono::milliseconds(2);

// One keep-alive connection: the next request as soon as the answer came.
class HttpLoop : public std::enable_shared_from_this<HttpLoop> {
  public:
    HttpLoop(asio::io_context& io, const WebTarget& web, std::string from, const WebFloodSpec& spec,
             WebFloodCounters& counters, Stopping stopping)
        : socket_(io),
          timer_(io),
          web_(web),
          from_(std::move(from)),
          token_(spec.token),
          targets_(spec.targets),
          counters_(counters),
          stopping_(std::move(stopping)) {}

    // Connects after `delay`: the floods come up one by one, not as 56
    // unauthenticated connections at once (gport-web admits 48 of those).
    void start(std::chrono::milliseconds delay) {
        timer_.expires_after(delay);
        timer_.async_wait([self = shared_from_this()](beast::error_code e) {
            if (!e && !*self->stopping_) {
                self->connect();
            }
        });
    }
    void connect() {
        beast::error_code ec;
        socket_.close(ec);
        socket_.open(tcp::v4(), ec);
        socket_.bind(tcp::endpoint(asio::ip::make_address(from_), 0), ec);
        socket_.set_option(tcp::no_delay(true), ec);
        buffer_.clear();
        const tcp::endpoint to(asio::ip::make_address("127.0.0.1"), web_.port);
        socket_.async_connect(to, [self = shared_from_this()](beast::error_code e) {
            e ? self->failed(e) : self->next();
        });
    }
    void close() {
        timer_.cancel();
        beast::error_code ec;
        socket_.close(ec);
    }

  private:
    void failed(const beast::error_code& e) {
        if (*stopping_) {
            return;  // our own close
        }
        counters_.count_error(e.message());
        reconnect();
    }
    void reconnect() {
        if (*stopping_) {
            return;
        }
        timer_.expires_after(kReconnectDelay);
        timer_.async_wait([self = shared_from_this()](beast::error_code e) {
            if (!e && !*self->stopping_) {
                self->connect();
            }
        });
    }
    void next() {
        if (*stopping_) {
            return;
        }
        request_ =
            bearer_request(http::verb::get, targets_[next_++ % targets_.size()], web_, token_);
        http::async_write(socket_, request_,
                          [self = shared_from_this()](beast::error_code e, std::size_t) {
                              e ? self->failed(e) : self->read();
                          });
    }
    void read() {
        parser_.emplace();
        parser_->body_limit(64 * 1024 * 1024);
        http::async_read(socket_, buffer_, *parser_,
                         [self = shared_from_this()](beast::error_code e, std::size_t) {
                             e ? self->failed(e) : self->answered();
                         });
    }
    void answered() {
        const auto& response = parser_->get();
        ++counters_.answers;
        counters_.body_bytes += response.body().size();
        counters_.count_status(response.result_int());
        response.keep_alive() ? next() : reconnect();
    }

    tcp::socket socket_;
    asio::steady_timer timer_;
    WebTarget web_;
    std::string from_;
    std::string token_;
    std::vector<std::string> targets_;
    WebFloodCounters& counters_;
    Stopping stopping_;
    std::size_t next_ = 0;
    beast::flat_buffer buffer_;
    http::request<http::string_body> request_;
    std::optional<http::response_parser<http::string_body>> parser_;
};

// A control WebSocket that reads everything and jogs at a fixed rate.
class JogSocket : public std::enable_shared_from_this<JogSocket> {
  public:
    JogSocket(std::unique_ptr<WebSocket> ws, const WebFloodSpec& spec, WebFloodCounters& counters,
              Stopping stopping)
        : ws_(std::move(ws)),
          timer_(ws_->get_executor()),
          text_(fmt::format(R"({{"type":"jog","pitch":0,"yaw":{},"roll":0}})", spec.jog_yaw_dps)),
          period_(std::chrono::duration<double>(1.0 / spec.jog_hz)),
          counters_(counters),
          stopping_(std::move(stopping)) {}

    void start() {
        read();
        tick();
    }
    void close() {
        timer_.cancel();
        beast::error_code ec;
        beast::get_lowest_layer(*ws_).close(ec);
    }

  private:
    void read() {
        ws_->async_read(buffer_, [self = shared_from_this()](beast::error_code e, std::size_t) {
            if (e) {
                self->counters_.ws_closed += *self->stopping_ ? 0 : 1;
                return;
            }
            self->buffer_.consume(self->buffer_.size());
            self->read();
        });
    }
    void tick() {
        timer_.expires_after(std::chrono::duration_cast<std::chrono::nanoseconds>(period_));
        timer_.async_wait([self = shared_from_this()](beast::error_code e) {
            if (e || *self->stopping_) {
                return;
            }
            self->write();
            self->tick();
        });
    }
    void write() {
        if (writing_) {
            return;
        }
        writing_ = true;
        ws_->async_write(asio::buffer(text_),
                         [self = shared_from_this()](beast::error_code e, std::size_t) {
                             self->writing_ = false;
                             self->counters_.jogs += e ? 0 : 1;
                         });
    }

    std::unique_ptr<WebSocket> ws_;
    asio::steady_timer timer_;
    std::string text_;
    std::chrono::duration<double> period_;
    WebFloodCounters& counters_;
    Stopping stopping_;
    beast::flat_buffer buffer_;
    bool writing_ = false;
};

}  // namespace

void WebFloodCounters::count_status(unsigned status) {
    if (status / 100 == 2) {
        return;
    }
    ++refused;
    std::lock_guard lock(mutex_);
    ++statuses_[status];
}

void WebFloodCounters::count_error(const std::string& what) {
    ++errors;
    std::lock_guard lock(mutex_);
    if (first_error_.empty()) {
        first_error_ = what;
    }
}

std::string WebFloodCounters::summary() const {
    std::lock_guard lock(mutex_);
    std::string text;
    for (const auto& [status, n] : statuses_) {
        text += fmt::format("{} answered {}; ", n, status);
    }
    if (!first_error_.empty()) {
        text += fmt::format("{} transport errors (first: {}); ", errors.load(), first_error_);
    }
    return text;
}

WebFloodSpec web_flood_spec(const std::string& flood, const WebTarget& web) {
    WebFloodSpec spec;
    if (flood == "view-status" || flood == "view-mixed") {
        spec.http_connections = 56;
        spec.token = web.view_token;
        spec.targets = {"/api/status"};
        if (flood == "view-mixed") {
            spec.targets.insert(spec.targets.end(), {"/api/limits", "/api/settings"});
        }
    } else if (flood == "csv") {
        spec.http_connections = 8;
        spec.token = web.view_token;
        spec.targets = {"/api/captures.csv"};
    } else if (flood == "jog") {
        spec.jog_sockets = 20;
    }
    return spec;
}

WebFlood::WebFlood(const WebTarget& web, const WebFloodSpec& spec) {
    int peer = 0;
    for (int i = 0; i < spec.http_connections; ++i, ++peer) {
        auto loop = std::make_shared<HttpLoop>(io_, web, peer_address(peer / kPeersPerAddress),
                                               spec, counters_, stopping_);
        loop->start(i * kConnectStagger);
        closers_.emplace_back([loop] { loop->close(); });
    }
    for (int i = 0; i < spec.jog_sockets; ++i, ++peer) {
        auto ws = open_live(io_, peer_address(peer / kPeersPerAddress), web, web.control_token);
        auto jog = std::make_shared<JogSocket>(std::move(ws), spec, counters_, stopping_);
        jog->start();
        closers_.emplace_back([jog] { jog->close(); });
    }
    thread_ = std::thread([this] { io_.run(); });
}

WebFlood::~WebFlood() {
    stop();
}

void WebFlood::stop() {
    if (!thread_.joinable()) {
        return;
    }
    *stopping_ = true;
    asio::post(io_, [this] {
        for (auto& close : closers_) {
            close();
        }
    });
    thread_.join();
}

}  // namespace gport::bench::relay
