// PtySimulator: the simulated gimbal served on a pseudo-terminal, on the
// caller's Asio io_context (single-threaded). gport-sim is a thin wrapper
// around it, and gportd --simulate embeds it:
//
//   boost::asio::io_context io;
//   gport::sim::PtySimulator sim(io, {});
//   open_serial(sim.device_path());   // the slave side, raw, 115200 8N1
//   ...                               // io.run(); sim.stop() to end
//
// While no process has the slave open, output is dropped (as a UART with
// nobody listening); while the client is not reading, writes that do not fit
// are dropped too. The simulator never blocks its io_context.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "gport/sim/faults.hpp"
#include "gport/sim/model.hpp"

namespace boost::asio {
class io_context;
}  // namespace boost::asio

namespace gport::sim {

struct SimOptions {
    ModelOptions model;
    FaultOptions faults;
    std::string link_path;    // keep a symlink here to the slave; empty: none
    int slave_gid = -1;       // every slave's group (--group); -1: as devpts makes it
    unsigned slave_mode = 0;  // every slave's mode (--mode); 0: as devpts makes it
    bool pace = false;        // space writes as a 115200-baud UART would (86.8 µs a byte)
    // The line rate in both directions (8N1: 10 bits a byte), 0 = off. The
    // client's bytes are read at most baud/10 a second, so they wait in the
    // pty's buffer as they would in a UART's, and output is paced at the same
    // rate (as `pace` does at 115200). A received frame's trace time is when
    // its last byte arrived at that rate.
    unsigned baud = 0;
    std::string record_path;  // record both directions here; empty: don't
    std::string replay_path;  // play this recording's tx side instead of the model
    // Receives one JSON line (no newline) per frame received, bad frame and
    // simulator event (docs/simulator.md); empty: no trace.
    std::function<void(const std::string&)> trace;
};

// SimOptions::baud's range when not 0 (off).
inline constexpr unsigned kMinBaud = 300;
inline constexpr unsigned kMaxBaud = 4'000'000;

// Empty when usable; otherwise what is wrong and what is allowed.
std::optional<std::string> validate(const SimOptions& options);

struct SimStats {
    ModelStats model;
    FaultStats faults;
    std::uint64_t bytes_read = 0;        // from the client
    std::uint64_t read_backlog_max = 0;  // --baud: most bytes seen waiting in the pty
    std::uint64_t bytes_written = 0;     // to the client
    std::uint64_t bytes_dropped = 0;     // nobody listening, silence, full buffer
    std::uint64_t writes = 0;            // write() calls that wrote something
    std::uint64_t peer_opens = 0;        // times a client opened the slave
    std::uint64_t vanishes = 0;
    std::uint64_t pty_replacements =
        0;  // a client left the slave exclusive; see release_exclusive()
    std::uint64_t replayed_entries = 0;
};

class PtySimulator {
  public:
    // Creates the pty (and the link) and starts serving on `io`. Throws
    // std::invalid_argument for bad options, std::system_error when the pty
    // or link cannot be made, std::runtime_error for an unreadable recording.
    PtySimulator(boost::asio::io_context& io, SimOptions options);
    // Stops (see stop()).
    ~PtySimulator();
    PtySimulator(const PtySimulator&) = delete;
    PtySimulator& operator=(const PtySimulator&) = delete;

    // The path a client should open: the link when one was asked for (it
    // survives vanish/reappear), otherwise the current slave path.
    const std::string& device_path() const;
    // The current slave, e.g. /dev/pts/7 (changes after a reappear).
    const std::string& slave_path() const;

    // Closes the pty, removes the link and cancels the timers, so the
    // io_context runs out of work from this simulator. Idempotent. Call it
    // (like every member) on the io_context's thread, e.g. from a signal_set
    // handler, or while the io_context is not running.
    void stop();
    bool stopped() const;

    // Stops reading what the client writes, as a gimbal whose UART stalled:
    // the bytes wait in the kernel's pty buffer (a few KiB) and then the
    // client's writes block. Output (attitude) goes on. resume_reading()
    // reads the backlog and carries on. Both are idempotent.
    void pause_reading();
    void resume_reading();
    bool reading_paused() const;

    // True while a client has the slave open (as last seen by the simulator).
    bool peer_connected() const;
    SimStats stats() const;
    const GimbalModel& model() const;

  private:
    class Impl;
    std::shared_ptr<Impl> impl_;
};

}  // namespace gport::sim
