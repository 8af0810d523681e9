// The read path: the gimbal's bytes to frames (protocol::Decoder) to
// messages, each handed to its handler with the time the bytes arrived. The
// line's quality (CRC and header errors, garbage bytes) goes to the journal
// as one summary per interval, never one line per frame, so a noisy line
// cannot flood it.
#pragma once

#include <spdlog/logger.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "gport/daemon/events.hpp"
#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::daemon {

class FrameReader {
  public:
    struct Handlers {
        std::function<void(const protocol::Attitude&, SteadyTime, WallTime)> attitude;
        std::function<void(const protocol::SettingsBlock&)> settings_report;  // 0x14
        std::function<void()> settings_ack;                                   // 0x16
    };

    static constexpr std::chrono::milliseconds kQualityInterval{10'000};

    // `device` names the line in the journal's summaries, one at most every
    // `interval`.
    FrameReader(boost::asio::io_context& io, std::string device,
                std::shared_ptr<spdlog::logger> log, Handlers handlers,
                std::chrono::milliseconds interval = kQualityInterval);

    void feed(std::span<const std::uint8_t> bytes);
    // The device reopened: a frame cut in half by the close is dropped.
    void reset() { decoder_.reset(); }
    // Starts and stops the interval of the quality summaries.
    void start();
    void stop() { quality_timer_.cancel(); }

    const protocol::DecoderStats& stats() const { return decoder_.stats(); }
    // Frames whose CRC held but whose payload did not decode.
    std::uint64_t bad_messages() const { return bad_messages_; }

  private:
    void on_frame(const protocol::FrameView& frame, SteadyTime now, WallTime wall);
    void report_quality();

    std::string device_;
    std::shared_ptr<spdlog::logger> log_;
    Handlers handlers_;
    protocol::Decoder decoder_;
    std::chrono::milliseconds interval_;
    boost::asio::steady_timer quality_timer_;
    protocol::DecoderStats reported_{};
    std::uint64_t bad_messages_ = 0;
};

}  // namespace gport::daemon
