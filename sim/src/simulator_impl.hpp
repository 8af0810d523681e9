// PtySimulator's internals, shared by simulator.cpp (time, device, model),
// simulator_input.cpp (reading, at the line rate when asked) and
// simulator_output.cpp (writing, pacing, recording).
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gport/sim/faults.hpp"
#include "gport/sim/model.hpp"
#include "gport/sim/pty.hpp"
#include "gport/sim/recording.hpp"
#include "gport/sim/simulator.hpp"

namespace gport::sim {

class PtySimulator::Impl : public std::enable_shared_from_this<PtySimulator::Impl> {
  public:
    using Clock = std::chrono::steady_clock;

    Impl(boost::asio::io_context& io, SimOptions options);
    void start();
    void stop();

    const std::string& device_path() const;
    const std::string& slave_path() const { return slave_path_; }
    bool stopped() const { return stopped_; }
    bool peer_connected() const { return peer_; }
    void pause_reading();
    void resume_reading();
    bool reading_paused() const { return paused_; }
    SimStats stats() const;
    const GimbalModel& model() const { return model_; }

  private:
    // --- time and the tick (simulator.cpp)
    Duration elapsed() const { return Clock::now() - start_; }
    void trace(const std::string& line) const;
    void event(std::string_view name, std::string_view path = {}, std::string_view error = {});
    void schedule_tick(Duration now);
    void on_tick();
    void apply_schedule(Duration now);
    void produce(Duration now);
    void replay(Duration now);

    // --- the device (simulator.cpp)
    void open_device();
    void close_device();
    void check_peer(Duration now);
    void peer_gone();
    void release_exclusive_mode();
    void release_unseen_exclusive_mode(Duration now);
    void act_on(Exclusivity found);
    void replace_pty();

    // --- input (simulator_input.cpp)
    void arm_read();
    void on_readable();
    void read_all();
    void read_at_line_rate();
    void wait_for_line(Clock::time_point at);
    void handle_input(std::span<const std::uint8_t> bytes);
    void handle_at_line_rate(std::span<const std::uint8_t> bytes, Clock::time_point first_done);
    void input_failed();

    // --- output (simulator_output.cpp)
    // One byte on the line (8N1): at --baud, else 115200 for --pace.
    Clock::duration byte_time() const;
    bool paced() const { return options_.pace || options_.baud > 0; }
    bool can_send() const;
    void send(std::vector<Chunk> chunks);
    void send_frames(const GimbalModel::Frames& frames, Duration now);
    void write_now(const Chunk& chunk);
    void pump(bool busy = false);
    void record(Direction direction, std::span<const std::uint8_t> bytes);

    SimOptions options_;
    Clock::time_point start_;
    GimbalModel model_;
    FaultInjector faults_;
    FaultSchedule schedule_;
    std::optional<Recorder> recorder_;

    std::vector<RecordEntry> replay_;  // tx entries only
    std::size_t replay_next_ = 0;
    std::optional<Duration> replay_start_;

    boost::asio::posix::stream_descriptor device_;
    std::string slave_path_;
    SlaveLink link_;
    boost::asio::steady_timer tick_timer_;
    boost::asio::steady_timer pace_timer_;
    boost::asio::steady_timer line_timer_;  // --baud: the next bytes' arrival
    bool peer_ = false;
    Duration idle_check_due_{};        // release_unseen_exclusive_mode()
    bool idle_check_possible_ = true;  // false where TIOCGEXCL fails (qemu-user)
    bool reading_ = false;
    bool pacing_ = false;
    bool paused_ = false;  // pause_reading(): the client's bytes stay in the pty
    bool stopped_ = false;

    std::deque<Chunk> queue_;  // paced output waiting for the wire
    std::size_t queued_bytes_ = 0;
    Clock::time_point line_free_;  // paced: when the last queued byte has left

    // --baud, input: when the last byte read had fully arrived, and whether
    // bytes were left waiting in the pty (the line stayed busy since).
    Clock::time_point rx_line_;
    bool rx_backlog_ = false;
    bool line_waiting_ = false;              // line_timer_ armed
    std::optional<Duration> rx_trace_time_;  // a received frame's time for the trace

    SimStats stats_;
};

}  // namespace gport::sim
