#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <stdexcept>

#include "gport/sim/trace.hpp"
#include "simulator_impl.hpp"

namespace gport::sim {
namespace {

namespace asio = boost::asio;

// How often the device and the schedule are looked at when no frame is due:
// bounds how late a client's open is noticed.
constexpr Duration kHousekeeping = std::chrono::milliseconds(10);

double to_ms(Duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
}

std::vector<RecordEntry> load_tx(const std::string& path) {
    auto loaded = load_recording(path);
    if (!loaded) {
        throw std::runtime_error(loaded.error().message);
    }
    std::vector<RecordEntry> tx;
    for (auto& e : std::move(loaded).value()) {
        if (e.direction == Direction::kTx) {
            tx.push_back(std::move(e));
        }
    }
    return tx;
}

}  // namespace

std::optional<std::string> validate(const SimOptions& o) {
    if (auto e = validate(o.model)) {
        return e;
    }
    if (auto e = validate(o.faults)) {
        return e;
    }
    const FaultOptions none;
    const bool faults = o.faults.noise_bytes_per_s > 0 || o.faults.corrupt_fraction > 0 ||
                        o.faults.shape != none.shape || o.faults.silence_for > Duration::zero() ||
                        o.faults.vanish_for > Duration::zero();
    if (!o.replay_path.empty() && faults) {
        return "a replay plays the recorded bytes as they were; it cannot be combined with fault "
               "injection";
    }
    if (!o.replay_path.empty() && o.replay_path == o.record_path) {
        return "cannot record into the recording being replayed";
    }
    if (o.baud != 0 && (o.baud < kMinBaud || o.baud > kMaxBaud)) {
        return fmt::format("baud must be 0 (off) or from {} to {}, got {}", kMinBaud, kMaxBaud,
                           o.baud);
    }
    return std::nullopt;
}

PtySimulator::Impl::Impl(asio::io_context& io, SimOptions options)
    : options_(std::move(options)),
      start_(Clock::now()),
      model_(options_.model),
      faults_(options_.faults),
      schedule_(options_.faults),
      device_(io),
      link_(options_.link_path),
      tick_timer_(io),
      pace_timer_(io),
      line_timer_(io),
      line_free_(start_),
      rx_line_(start_) {
    if (auto error = validate(options_)) {
        throw std::invalid_argument(*error);
    }
    if (!options_.replay_path.empty()) {
        replay_ = load_tx(options_.replay_path);
    }
    if (!options_.record_path.empty()) {
        recorder_.emplace(options_.record_path);
    }
    if (options_.trace) {
        model_.set_listener([this](const Received& r) {
            trace(trace_received(to_ms(rx_trace_time_.value_or(model_.now())), r));
        });
    }
    open_device();
}

void PtySimulator::Impl::start() {
    schedule_tick(Duration::zero());
}

void PtySimulator::Impl::stop() {
    if (stopped_) {
        return;
    }
    stopped_ = true;
    tick_timer_.cancel();
    pace_timer_.cancel();
    line_timer_.cancel();
    close_device();
}

const std::string& PtySimulator::Impl::device_path() const {
    return link_.path().empty() ? slave_path_ : link_.path();
}

SimStats PtySimulator::Impl::stats() const {
    SimStats s = stats_;
    s.model = model_.stats();
    s.faults = faults_.stats();
    return s;
}

void PtySimulator::Impl::trace(const std::string& line) const {
    if (options_.trace) {
        options_.trace(line);
    }
}

void PtySimulator::Impl::event(std::string_view name, std::string_view path,
                               std::string_view error) {
    if (options_.trace) {
        trace(trace_event(to_ms(elapsed()), name, path, error));
    }
}

// The next deadline is the earliest thing due, each computed from its own
// schedule (never "now + period"), so the stream does not drift.
void PtySimulator::Impl::schedule_tick(Duration now) {
    if (stopped_) {
        return;
    }
    Duration next = now + kHousekeeping;
    if (replay_.empty()) {
        next = std::min(next, model_.next_emission());
    } else if (replay_start_ && replay_next_ < replay_.size()) {
        next = std::min(next, *replay_start_ + replay_[replay_next_].t - replay_.front().t);
    }
    next = std::min({next, faults_.next_flush(), schedule_.next_change(now)});
    tick_timer_.expires_at(start_ + next);
    tick_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& ec) {
        if (!ec && !self->stopped_) {
            self->on_tick();
        }
    });
}

void PtySimulator::Impl::on_tick() {
    const Duration now = elapsed();
    apply_schedule(now);
    if (device_.is_open()) {
        check_peer(now);
    }
    produce(now);
    schedule_tick(now);
}

void PtySimulator::Impl::apply_schedule(Duration now) {
    for (auto e : schedule_.update(now)) {
        if (e == FaultSchedule::Event::kVanish) {
            ++stats_.vanishes;
            event(to_string(e), device_path());  // announced first: readers see it before EIO
            close_device();
        } else if (e == FaultSchedule::Event::kReappear) {
            open_device();
            event(to_string(e), device_path());
        } else {
            event(to_string(e));
        }
    }
    if (!schedule_.vanished() && !device_.is_open()) {
        open_device();  // an earlier reopen failed: keep trying, as udev would
    }
}

void PtySimulator::Impl::produce(Duration now) {
    if (replay_.empty()) {
        send_frames(model_.step(now), now);
        return;
    }
    model_.step(now);  // keeps time for the trace; its output is not used
    replay(now);
}

// The replay clock starts when a client opens the slave, so the client sees
// the recording from its first byte.
void PtySimulator::Impl::replay(Duration now) {
    if (!replay_start_) {
        if (!peer_) {
            return;
        }
        replay_start_ = now;
    }
    const Duration offset = replay_.front().t;
    std::vector<Chunk> due;
    while (replay_next_ < replay_.size() &&
           *replay_start_ + replay_[replay_next_].t - offset <= now) {
        due.push_back(replay_[replay_next_++].bytes);
        ++stats_.replayed_entries;
    }
    send(std::move(due));
    if (replay_next_ == replay_.size()) {
        event("replay_end");
        replay_next_ = replay_.size() + 1;  // report the end once
    }
}

void PtySimulator::Impl::open_device() {
    try {
        PtyMaster pty = open_pty({options_.slave_gid, options_.slave_mode});
        device_.assign(pty.fd);
        slave_path_ = pty.slave_path;
        link_.point_to(slave_path_);
    } catch (const std::exception& e) {
        if (device_.is_open()) {
            boost::system::error_code ignored;
            device_.close(ignored);
        }
        if (slave_path_.empty()) {
            throw;  // the first open: the caller decides
        }
        event("reopen_failed", device_path(), e.what());
    }
}

void PtySimulator::Impl::close_device() {
    if (device_.is_open()) {
        boost::system::error_code ignored;
        device_.close(ignored);
    }
    reading_ = false;
    peer_ = false;
    rx_backlog_ = false;
    queue_.clear();
    queued_bytes_ = 0;
    link_.remove();
}

void PtySimulator::Impl::check_peer(Duration now) {
    const bool present = peer_present(device_.native_handle());
    if (present && !peer_) {
        peer_ = true;
        ++stats_.peer_opens;
        event("peer_open", slave_path_);
    } else if (!present && peer_) {
        peer_gone();
    } else if (!present) {
        release_unseen_exclusive_mode(now);
    }
    if (peer_ && !reading_ && !line_waiting_ && !paused_) {
        arm_read();
    }
}

void PtySimulator::Impl::peer_gone() {
    peer_ = false;
    queue_.clear();
    queued_bytes_ = 0;
    event("peer_closed", slave_path_);
    release_exclusive_mode();
}

// A client that set TIOCEXCL and died (kill -9) or closed without clearing
// it would keep every later open refused with EBUSY, since the mode lives as
// long as our master. A real adapter drops it on the last close; so do we:
// clear it if we may, else move to a fresh pty under the same link.
void PtySimulator::Impl::release_exclusive_mode() {
    Exclusivity found = Exclusivity::kNone;
    try {
        found = release_exclusive(slave_path_);
    } catch (const std::system_error& e) {
        event("exclusive_stuck", slave_path_, e.what());
        return;
    }
    act_on(found);
}

// A client that opened the slave, set TIOCEXCL and closed it between two
// ticks (a daemon stopped right after it opened, or a tick delayed on a
// loaded machine) was never seen, so peer_gone() never ran for it. While no
// client is present the mode is therefore checked every 100 ms as well. Where
// the mode cannot be read (qemu-user has no TIOCGEXCL) this check gives up
// quietly: peer_gone() already reports that on every departure.
void PtySimulator::Impl::release_unseen_exclusive_mode(Duration now) {
    constexpr Duration kEvery = std::chrono::milliseconds(100);
    if (!idle_check_possible_ || now < idle_check_due_) {
        return;
    }
    idle_check_due_ = now + kEvery;
    Exclusivity found = Exclusivity::kNone;
    try {
        found = release_exclusive(slave_path_);
    } catch (const std::system_error&) {
        idle_check_possible_ = false;
        return;
    }
    if (found != Exclusivity::kNone) {
        event("unseen_client_left_exclusive", slave_path_);
        act_on(found);
    }
}

void PtySimulator::Impl::act_on(Exclusivity found) {
    if (found == Exclusivity::kCleared) {
        event("exclusive_cleared", slave_path_);
    } else if (found == Exclusivity::kStuck) {
        if (link_.path().empty()) {
            event("exclusive_stuck", slave_path_,
                  "the slave stays exclusive (TIOCEXCL): clearing it needs CAP_SYS_ADMIN, and "
                  "without --link the pty cannot be replaced");
            idle_check_possible_ = false;  // said once; the idle check would repeat it
            return;
        }
        replace_pty();
    }
}

// The old master closes (its slave, and the stuck mode, go with it) and the
// link moves to a new pty in one rename, so a client reopening the link
// never finds it missing.
void PtySimulator::Impl::replace_pty() {
    boost::system::error_code ignored;
    device_.close(ignored);
    reading_ = false;
    open_device();
    if (device_.is_open()) {
        ++stats_.pty_replacements;
        event("pty_replaced", slave_path_);
    }
}

// ---- PtySimulator ------------------------------------------------------------

PtySimulator::PtySimulator(asio::io_context& io, SimOptions options)
    : impl_(std::make_shared<Impl>(io, std::move(options))) {
    impl_->start();
}

PtySimulator::~PtySimulator() {
    impl_->stop();
}

const std::string& PtySimulator::device_path() const {
    return impl_->device_path();
}
const std::string& PtySimulator::slave_path() const {
    return impl_->slave_path();
}
void PtySimulator::stop() {
    impl_->stop();
}
void PtySimulator::pause_reading() {
    impl_->pause_reading();
}
void PtySimulator::resume_reading() {
    impl_->resume_reading();
}
bool PtySimulator::reading_paused() const {
    return impl_->reading_paused();
}
bool PtySimulator::stopped() const {
    return impl_->stopped();
}
bool PtySimulator::peer_connected() const {
    return impl_->peer_connected();
}
SimStats PtySimulator::stats() const {
    return impl_->stats();
}
const GimbalModel& PtySimulator::model() const {
    return impl_->model();
}

}  // namespace gport::sim
