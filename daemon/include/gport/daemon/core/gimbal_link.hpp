// The gimbal's end of the core: the serial port with its reconnects, the read
// path (FrameReader) and the link's health (LinkMonitor), and whether gportd
// is shutting down. Core gives it the messages' handlers, sends its frames
// through it and reads its figures into the status; Motion sends its 0x85
// frames through it too (stops first, write_queue.hpp): the one way to the
// wire.
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <functional>
#include <memory>
#include <optional>
#include <string_view>

#include "gport/config/config.hpp"
#include "gport/daemon/api.hpp"
#include "gport/daemon/core/frame_reader.hpp"
#include "gport/daemon/core/link_monitor.hpp"
#include "gport/daemon/core/serial_port.hpp"

namespace gport::daemon {

class GimbalLink {
  public:
    struct Handlers {
        FrameReader::Handlers messages;
        std::function<void()> opened;  // before the monitor's link event
        LinkMonitor::OnChange link;
    };

    GimbalLink(boost::asio::io_context& io, const config::Config& config,
               std::shared_ptr<spdlog::logger> log, Handlers handlers);

    // Opens the device (retrying forever in the background).
    void start();
    // From now on nothing is read and send() refuses: the frames queued
    // (the stop among them) are written, bounded by `limit`, then the device
    // closes and done is called, from the loop.
    void shutdown(std::chrono::milliseconds limit, std::function<void()> done);

    SerialPort& port() { return port_; }
    bool open() const { return port_.is_open(); }
    bool ready() const { return port_.is_open() && !stopping_; }
    bool stopping() const { return stopping_; }
    // The one kLinkDown error (link_down_error), then what follows for this
    // request (may be empty).
    CommandError link_down(std::string_view consequence = {}) const;
    // Queues a frame for the device, or the kLinkDown error (also while
    // shutting down: only what was queued before goes). `kind` orders the
    // queue (a stop first; a stop sent while the device is closed is owed to
    // it: serial_port.hpp).
    std::optional<CommandError> send(const protocol::Frame& frame,
                                     FrameKind kind = FrameKind::kOther);
    // An attitude arrived (the core calls this once it holds the sample).
    void attitude_received(SteadyTime now) { monitor_.attitude_received(now); }

    // The link, the device and the counters of the wire in both directions.
    void report(Status& status) const;

  private:
    FrameReader reader_;
    SerialPort port_;
    LinkMonitor monitor_;
    bool stopping_ = false;
};

}  // namespace gport::daemon
