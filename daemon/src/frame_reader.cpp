#include "gport/daemon/core/frame_reader.hpp"

#include <type_traits>
#include <variant>

namespace gport::daemon {

namespace gp = gport::protocol;

FrameReader::FrameReader(boost::asio::io_context& io, std::string device,
                         std::shared_ptr<spdlog::logger> log, Handlers handlers,
                         std::chrono::milliseconds interval)
    : device_(std::move(device)),
      log_(std::move(log)),
      handlers_(std::move(handlers)),
      interval_(interval),
      quality_timer_(io) {}

void FrameReader::feed(std::span<const std::uint8_t> bytes) {
    const auto now = std::chrono::steady_clock::now();
    const auto wall = std::chrono::system_clock::now();
    decoder_.feed(bytes, [&](const gp::FrameView& frame) { on_frame(frame, now, wall); });
}

void FrameReader::on_frame(const gp::FrameView& frame, SteadyTime now, WallTime wall) {
    auto message = gp::decode(frame);
    if (!message) {
        ++bad_messages_;
        log_->debug("ignoring frame from the gimbal: {}", message.error().message);
        return;
    }
    std::visit(
        [&](const auto& m) {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, gp::Attitude>) {
                handlers_.attitude(m, now, wall);
            } else if constexpr (std::is_same_v<T, gp::SettingsReport>) {
                handlers_.settings_report(m.block);
            } else if constexpr (std::is_same_v<T, gp::SetSettingsAck>) {
                handlers_.settings_ack();
            } else {
                log_->debug("ignoring command 0x{:02X} from the gimbal", frame.command);
            }
        },
        *message);
}

void FrameReader::start() {
    quality_timer_.expires_after(interval_);
    quality_timer_.async_wait([this](boost::system::error_code ec) {
        if (!ec) {
            report_quality();
            start();
        }
    });
}

void FrameReader::report_quality() {
    const auto& now = decoder_.stats();
    const auto crc = now.crc_errors - reported_.crc_errors;
    const auto header = now.header_errors - reported_.header_errors;
    const auto garbage = now.garbage_bytes - reported_.garbage_bytes;
    if (crc + header + garbage > 0) {
        log_->warn(
            "noisy line on {}: {} CRC errors, {} header errors, {} garbage bytes in the "
            "last {} s",
            device_, crc, header, garbage, std::chrono::duration<double>(interval_).count());
    }
    reported_ = now;
}

}  // namespace gport::daemon
