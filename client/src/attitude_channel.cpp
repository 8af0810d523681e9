#include "gport/client/attitude_channel.hpp"

#include <sys/eventfd.h>
#include <sys/mman.h>
#include <sys/stat.h>
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

Error channel_error(const std::string& what) {
    return Error(ErrorCode::kBadReply, "attitude channel: " + what);
}

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

std::unique_ptr<AttitudeChannel::Impl> AttitudeChannel::Impl::map(int fd) {
    struct stat info {};
    if (::fstat(fd, &info) != 0) {
        throw channel_error(std::string("cannot examine the descriptor: ") + std::strerror(errno));
    }
    if (info.st_size <= 0) {
        throw channel_error("the block is empty");
    }
    const auto size = static_cast<std::size_t>(info.st_size);
    void* memory = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        throw channel_error(std::string("cannot map the block: ") + std::strerror(errno));
    }
    if (auto problem = base::RingReader::check(memory, size)) {
        ::munmap(memory, size);
        throw channel_error(*problem);
    }
    return std::make_unique<Impl>(memory, size);
}

AttitudeChannel AttitudeChannel::Impl::adopt(int fd) {
    if (fd < 0) {
        throw Error(ErrorCode::kBadReply,
                    "attitude channel: gportd's reply carried no file descriptor");
    }
    try {
        auto impl = map(fd);
        ::close(fd);
        return AttitudeChannel(std::move(impl));
    } catch (...) {
        ::close(fd);
        throw;
    }
}

AttitudeChannel::Impl::~Impl() {
    ::munmap(const_cast<void*>(memory), size);
}

std::optional<AttitudeSample> AttitudeChannel::Impl::take() {
    if (from_first && reader.published() > 0) {
        from_first = false;
        if (auto first = reader.read(1)) {
            cursor = 1;
            return to_attitude(*first, missed.load(std::memory_order_relaxed));
        }
    }
    std::uint64_t lost = missed.load(std::memory_order_relaxed);
    auto sample = reader.next(cursor, lost);
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
        // the look changes it, and the wait then returns at once.
        const std::uint32_t seen = reader.wake_word().load(std::memory_order_acquire);
        if (auto sample = take()) {
            return sample;
        }
        const auto left = deadline - std::chrono::steady_clock::now();
        if (reader.closed() || left <= std::chrono::steady_clock::duration::zero()) {
            return std::nullopt;
        }
        base::futex_wait(reader.wake_word(), seen, left);
    }
}

RingWaker::RingWaker(const base::RingReader& reader)
    : word_(reader.wake_word()),
      seen_(word_.load(std::memory_order_acquire)),
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
    // FUTEX_WAKE only needs read access; it may also wake other readers of
    // the block, which find nothing new and sleep again.
    base::futex_wake_all(const_cast<std::atomic<std::uint32_t>&>(word_));
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
        base::futex_wait(word_, seen, kWakerSlice);
        const std::uint32_t now = word_.load(std::memory_order_acquire);
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
    auto sample = impl_->reader.latest();
    if (!sample) {
        return std::nullopt;
    }
    return to_attitude(*sample, impl_->missed.load(std::memory_order_relaxed));
}

std::uint64_t AttitudeChannel::missed() const {
    return impl_ ? impl_->missed.load(std::memory_order_relaxed) : 0;
}

bool AttitudeChannel::closed() const {
    return !impl_ || impl_->reader.closed();
}

}  // namespace gport::client
