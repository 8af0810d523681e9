#include "gport/daemon/core/gimbal_link.hpp"

namespace gport::daemon {

GimbalLink::GimbalLink(boost::asio::io_context& io, const config::Config& config,
                       std::shared_ptr<spdlog::logger> log, Handlers handlers)
    : reader_(io, config.serial.device, log, std::move(handlers.messages)),
      port_(
          io, config.serial, config.link,
          SerialPort::Handlers{[this](std::span<const std::uint8_t> bytes) { reader_.feed(bytes); },
                               [this, opened = std::move(handlers.opened)] {
                                   reader_.reset();
                                   opened();
                                   monitor_.device_opened();
                               },
                               [this](const std::string& reason) {
                                   monitor_.device_closed("device closed: " + reason);
                               }},
          log),
      monitor_(io, config.link.stale_after, std::move(handlers.link)) {}

void GimbalLink::start() {
    port_.start();
    reader_.start();
}

void GimbalLink::shutdown(std::chrono::milliseconds limit, std::function<void()> done) {
    stopping_ = true;
    reader_.stop();
    port_.drain(limit, [this, done = std::move(done)] {
        monitor_.stop();
        port_.stop();
        done();
    });
}

CommandError GimbalLink::link_down(std::string_view consequence) const {
    return link_down_error(port_, stopping_, consequence);
}

std::optional<CommandError> GimbalLink::send(const protocol::Frame& frame, FrameKind kind) {
    if (!stopping_ && port_.send(frame, kind)) {
        return std::nullopt;
    }
    return link_down();
}

void GimbalLink::report(Status& s) const {
    s.link = monitor_.state();
    s.link_reason = monitor_.reason();
    s.device = port_.device();
    s.device_open = port_.is_open();
    if (!s.device_open && !port_.open_error().empty()) {
        s.device_error = port_.open_error();
    }
    const auto& d = reader_.stats();
    const auto l = port_.stats();
    auto& c = s.counters;
    c.frames_in = d.frames;
    c.bytes_in = d.bytes;
    c.frames_out = l.frames_out;
    c.bytes_out = l.bytes_out;
    c.crc_errors = d.crc_errors;
    c.header_errors = d.header_errors;
    c.garbage_bytes = d.garbage_bytes;
    c.resyncs = d.resyncs;
    c.bad_messages = reader_.bad_messages();
    c.device_opens = l.opens;
    c.device_failures = l.failures;
    c.stops_sent = l.stops_written;
    c.frames_replaced = l.frames_replaced;
    c.frames_refused = l.queue_overflows;
}

}  // namespace gport::daemon
