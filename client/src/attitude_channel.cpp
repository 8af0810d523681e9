#include "gport/client/attitude_channel.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include "gport/base/futex.hpp"
#include "gport/client/error.hpp"
#include "ring_channel.hpp"

namespace gport::client {
namespace {

// The waker looks at its stop flag at least this often (a stop also wakes
// it at once).
constexpr auto kWakerSlice = std::chrono::milliseconds(500);

}  // namespace

AttitudeSample to_attitude(const base::RingSample& s, std::uint64_t dropped) {
    AttitudeSample a;
    a.seq = s.seq;
    a.time = s.t;
    a.imu = Axes{s.imu[0], s.imu[1], s.imu[2]};
    a.hall = Axes{s.hall[0], s.hall[1], s.hall[2]};
    if (s.has_rates) {
        a.rates = Rates{Axes{s.hall_rates[0], s.hall_rates[1], s.hall_rates[2]},
                        ImuRates{s.imu_rates[0], s.imu_rates[1], s.imu_rates[2]}};
    }
    a.dropped = dropped;
    return a;
}

std::optional<AttitudeSample> AttitudeChannel::Impl::take() {
    const auto& ring = reader();
    if (from_first && ring.published() > 0) {
        from_first = false;
        if (auto first = ring.read(1)) {
            cursor = 1;
            return to_attitude(*first, missed.load(std::memory_order_relaxed));
        }
    }
    std::uint64_t lost = missed.load(std::memory_order_relaxed);
    auto sample = ring.next(cursor, lost);
    missed.store(lost, std::memory_order_relaxed);
    if (!sample) {
        return std::nullopt;
    }
    return to_attitude(*sample, lost);
}

std::optional<AttitudeSample> AttitudeChannel::Impl::next(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
        // Read the word before looking for samples: a sample published after
        // the look changes it, and the wait then returns at once. A new value
        // is passed on to this process's other waiters first.
        const std::uint32_t seen = mapping->load();
        mapping->relay(seen);
        if (auto sample = take()) {
            return sample;
        }
        const auto left = deadline - std::chrono::steady_clock::now();
        if (reader().closed() || left <= std::chrono::steady_clock::duration::zero()) {
            return std::nullopt;
        }
        mapping->wait(seen, left);
    }
}

RingWaker::RingWaker(std::shared_ptr<ChannelMapping> mapping)
    : mapping_(std::move(mapping)),
      seen_(mapping_->load()),
      eventfd_(::eventfd(1, EFD_CLOEXEC | EFD_NONBLOCK)) {
    if (eventfd_ < 0) {
        throw Error(
            ErrorCode::kTransport,
            std::string("attitude channel: cannot make an eventfd: ") + std::strerror(errno));
    }
    thread_ = std::thread([this] { run(); });
}

RingWaker::~RingWaker() {
    stop_.store(true, std::memory_order_release);
    // FUTEX_WAKE only needs read access; it may also wake this process's
    // other readers of the connection, which find nothing new and sleep again.
    base::futex_wake_all(mapping_->word());
    thread_.join();
    ::close(eventfd_);
}

void RingWaker::reset() noexcept {
    std::uint64_t count = 0;
    [[maybe_unused]] const auto n = ::read(eventfd_, &count, sizeof(count));
}

void RingWaker::run() {
    std::uint32_t seen = seen_;
    while (!stop_.load(std::memory_order_acquire)) {
        mapping_->wait(seen, kWakerSlice);
        const std::uint32_t now = mapping_->load();
        mapping_->relay(now);
        if (now != seen) {
            seen = now;
            const std::uint64_t one = 1;
            [[maybe_unused]] const auto n = ::write(eventfd_, &one, sizeof(one));
        }
    }
}

AttitudeChannel::AttitudeChannel() = default;
AttitudeChannel::AttitudeChannel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
AttitudeChannel::AttitudeChannel(AttitudeChannel&& other) noexcept = default;
AttitudeChannel& AttitudeChannel::operator=(AttitudeChannel&& other) noexcept = default;
AttitudeChannel::~AttitudeChannel() = default;

std::optional<AttitudeSample> AttitudeChannel::next(std::chrono::milliseconds timeout) {
    return impl_ ? impl_->next(timeout) : std::nullopt;
}

std::optional<AttitudeSample> AttitudeChannel::latest() const {
    if (!impl_) {
        return std::nullopt;
    }
    auto sample = impl_->reader().latest();
    if (!sample) {
        return std::nullopt;
    }
    return to_attitude(*sample, impl_->missed.load(std::memory_order_relaxed));
}

std::uint64_t AttitudeChannel::missed() const {
    return impl_ ? impl_->missed.load(std::memory_order_relaxed) : 0;
}

bool AttitudeChannel::closed() const {
    return !impl_ || impl_->reader().closed();
}

}  // namespace gport::client
