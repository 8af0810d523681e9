// The probe's control WebSocket reads on a thread of its own (gport-web
// pushes attitude at 50 Hz and status every second); its writes are posted
// there, so a jog or stop leaves within microseconds of the probe's stamp.
#include <fmt/format.h>

#include <boost/asio/post.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <chrono>
#include <deque>
#include <mutex>
#include <thread>

#include "../e2e/posix.hpp"
#include "scenarios.hpp"
#include "web_floods.hpp"

namespace gport::bench::relay {
namespace {

constexpr const char* kJog = R"({"type":"jog","pitch":0,"yaw":5,"roll":0})";
constexpr const char* kStop = R"({"type":"stop"})";

class ProbeSocket {
  public:
    explicit ProbeSocket(const WebTarget& web)
        : ws_(open_live(io_, "127.0.0.1", web, web.control_token)) {
        read();
        thread_ = std::thread([this] { io_.run(); });
    }
    ~ProbeSocket() {
        asio::post(io_, [this] {
            beast::error_code ec;
            beast::get_lowest_layer(*ws_).close(ec);
        });
        thread_.join();
    }
    ProbeSocket(const ProbeSocket&) = delete;
    ProbeSocket& operator=(const ProbeSocket&) = delete;

    void send(std::string text) {
        asio::post(io_, [this, text = std::move(text)]() mutable {
            outbox_.push_back(std::move(text));
            if (outbox_.size() == 1) {
                write_next();
            }
        });
    }
    std::uint64_t errors() const { return errors_.load(); }
    std::string first_error() const {
        std::lock_guard lock(mutex_);
        return first_error_;
    }
    bool closed() const { return closed_.load(); }

  private:
    void read() {
        ws_->async_read(buffer_, [this](beast::error_code e, std::size_t) {
            if (e) {
                closed_ = true;
                return;
            }
            auto text = beast::buffers_to_string(buffer_.data());
            if (text.find(R"("method":"error")") != std::string::npos) {
                std::lock_guard lock(mutex_);
                first_error_ = errors_++ == 0 ? std::move(text) : first_error_;
            }
            buffer_.consume(buffer_.size());
            read();
        });
    }
    void write_next() {
        ws_->async_write(asio::buffer(outbox_.front()), [this](beast::error_code e, std::size_t) {
            outbox_.pop_front();
            if (!e && !outbox_.empty()) {
                write_next();
            }
        });
    }

    asio::io_context io_;
    std::unique_ptr<WebSocket> ws_;
    beast::flat_buffer buffer_;
    std::deque<std::string> outbox_;
    std::atomic<std::uint64_t> errors_{0};
    mutable std::mutex mutex_;
    std::string first_error_;
    std::atomic<bool> closed_{false};
    std::thread thread_;
};

std::string flood_rate(const WebFloodCounters& c, std::uint64_t answers, std::uint64_t jogs,
                       double seconds) {
    if (c.jogs > 0) {
        return fmt::format("{:.0f} jogs/s", static_cast<double>(c.jogs - jogs) / seconds);
    }
    if (c.answers == 0 && c.errors == 0) {
        return "-";
    }
    return fmt::format("{:.0f} answers/s, {:.1f} MB bodies in all",
                       static_cast<double>(c.answers - answers) / seconds,
                       static_cast<double>(c.body_bytes) / 1e6);
}

std::string notes(const ProbeSocket& ws, int http_failures, const WebFloodCounters& c) {
    std::string text;
    if (ws.errors() > 0) {
        text += fmt::format("probe socket got {} error messages (first: {}); ", ws.errors(),
                            ws.first_error());
    }
    if (ws.closed()) {
        text += "gport-web closed the probe socket; ";
    }
    if (http_failures > 0) {
        text += fmt::format("{} POST /api/stop not answered 200; ", http_failures);
    }
    text += c.summary();
    if (c.ws_closed > 0) {
        text += fmt::format("gport-web closed {} flood sockets; ", c.ws_closed.load());
    }
    return text;
}

}  // namespace

ScenarioResult run_web_scenario(Rig& rig, const Options& options, const Scenario& scenario) {
    ScenarioResult result;
    result.scenario = scenario;
    const WebTarget& web = rig.web();
    ProbeSocket ws(web);
    HttpConnection http(web, web.control_token);
    const Marks before = rig.marks();
    WebFlood flood(web, web_flood_spec(scenario.flood, web));
    std::this_thread::sleep_for(std::chrono::duration<double>(options.flood_seconds));
    const std::uint64_t answers = flood.counters().answers;
    const std::uint64_t jogs = flood.counters().jogs;
    const auto start = now_ns();
    int http_failures = 0;
    ProbeHooks hooks;
    hooks.start_motion = [&] { ws.send(kJog); };
    hooks.send_stop = [&](int i) {
        if (i % 2 == 0) {
            ws.send(kStop);
        } else if (http.request(http::verb::post, "/api/stop") != 200u) {
            ++http_failures;
        }
    };
    result.probe = run_probe(rig.sim(), options.stops, options.spacing_ms, hooks);
    const double seconds = static_cast<double>(now_ns() - start) / 1e9;
    result.flood_rate = flood_rate(flood.counters(), answers, jogs, seconds);
    flood.stop();
    result.notes = notes(ws, http_failures, flood.counters());
    const Marks after = rig.marks();
    result.lease_endings = after.lease_endings - before.lease_endings;
    result.relay_drops = after.web_drops - before.web_drops;
    result.relay_alive = rig.web_alive();
    return result;
}

}  // namespace gport::bench::relay
