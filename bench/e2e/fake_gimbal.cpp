#include "fake_gimbal.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <ctime>
#include <stdexcept>

#include "gport/protocol/decoder.hpp"
#include "gport/protocol/messages.hpp"

namespace gport::bench {
namespace {

namespace proto = gport::protocol;

// The number after `key` in `line`, e.g. after "\"roll\":".
double number_after(std::string_view line, std::string_view key, std::size_t from) {
    const auto at = line.find(key, from);
    if (at == std::string_view::npos) {
        return -1;
    }
    double value = -1;
    const char* begin = line.data() + at + key.size();
    std::from_chars(begin, line.data() + line.size(), value);
    return value;
}

void make_raw(int fd) {
    termios tio{};
    if (::tcgetattr(fd, &tio) == 0) {
        ::cfmakeraw(&tio);
        ::tcsetattr(fd, TCSANOW, &tio);
    }
}

// The measuring threads run SCHED_FIFO when allowed (root, or CAP_SYS_NICE),
// so that a stamp is taken when the byte moves, not when a busy 2-core
// machine gets round to scheduling the benchmark. Falls back silently.
bool make_realtime() {
    sched_param param{};
    param.sched_priority = 10;
    return ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param) == 0;
}

proto::Frame frame_for(std::uint32_t counter) {
    proto::Attitude attitude;
    attitude.imu.roll = static_cast<std::int16_t>(counter % kCounterBase);
    attitude.imu.pitch = static_cast<std::int16_t>(counter / kCounterBase);
    attitude.hall = {-1921, -16, 466};
    return proto::encode(attitude);
}

std::string bytes_of(const proto::Frame& frame) {
    const auto bytes = frame.bytes();
    return {bytes.begin(), bytes.end()};
}

}  // namespace

std::uint32_t counter_of_line(std::string_view line) {
    const auto imu = line.find("\"imu\":{");
    if (imu == std::string_view::npos) {
        return 0;
    }
    const double roll = number_after(line, "\"roll\":", imu);
    const double pitch = number_after(line, "\"pitch\":", imu);
    if (roll < 0 || pitch < 0) {
        return 0;
    }
    return static_cast<std::uint32_t>(std::lround(roll * 100)) +
           kCounterBase * static_cast<std::uint32_t>(std::lround(pitch * 100));
}

FakeGimbal::FakeGimbal() : master_(::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC)) {
    if (!master_.valid() || ::grantpt(master_.get()) != 0 || ::unlockpt(master_.get()) != 0) {
        throw std::runtime_error(std::string("cannot make a pseudo-terminal: ") +
                                 std::strerror(errno));
    }
    slave_path_ = ::ptsname(master_.get());
    slave_ = Fd(::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
    if (!slave_.valid()) {
        throw std::runtime_error("cannot open " + slave_path_ + ": " + std::strerror(errno));
    }
    make_raw(slave_.get());  // no echo of our frames back to us before gportd opens it
    make_raw(master_.get());
    reader_ = std::thread([this] { read_loop(); });
}

FakeGimbal::~FakeGimbal() {
    stop_stream();
    stop_reader();
}

void FakeGimbal::start_stream(double rate_hz, std::size_t max_frames) {
    write_times_.assign(max_frames + 1, 0);
    writing_ = true;
    writer_ = std::thread([this, rate_hz, max_frames] { write_loop(rate_hz, max_frames); });
}

void FakeGimbal::stop_stream() {
    writing_ = false;
    if (writer_.joinable()) {
        writer_.join();
    }
}

void FakeGimbal::stop_reader() {
    reading_ = false;
    if (reader_.joinable()) {
        reader_.join();
    }
}

// Frame n falls due at start + n * period (absolute deadlines: no drift). A
// writer that fell behind sends the overdue frames at once and counts them.
void FakeGimbal::write_loop(double rate_hz, std::size_t max_frames) {
    realtime_ = make_realtime();
    const auto period_ns = static_cast<std::int64_t>(1e9 / rate_hz);
    const auto start = now_ns() + period_ns;
    for (std::uint32_t n = 1; n <= max_frames && writing_; ++n) {
        const auto due = start + (n - 1) * period_ns;
        const timespec at{static_cast<time_t>(due / 1'000'000'000), due % 1'000'000'000};
        while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) == EINTR) {
        }
        const std::string bytes = payload_ ? payload_(n) : bytes_of(frame_for(n));
        std::size_t done = 0;
        while (done < bytes.size()) {
            const auto w = ::write(master_.get(), bytes.data() + done, bytes.size() - done);
            if (w < 0 && errno != EINTR && errno != EAGAIN) {
                return;  // the pty is gone: nothing more to measure
            }
            done += w > 0 ? static_cast<std::size_t>(w) : 0;
        }
        const auto written = now_ns();
        write_times_[n] = written;
        if (written - due > period_ns) {
            ++late_;
        }
        written_ = n;
    }
}

void FakeGimbal::read_loop() {
    make_realtime();
    proto::Decoder decoder;
    std::uint8_t buffer[4096];
    while (reading_) {
        pollfd p{master_.get(), POLLIN, 0};
        if (::poll(&p, 1, 50) <= 0) {
            continue;
        }
        const auto n = ::read(master_.get(), buffer, sizeof(buffer));
        const auto t = now_ns();
        if (n <= 0) {
            continue;  // EIO while nobody has the slave open: wait for gportd
        }
        decoder.feed({buffer, static_cast<std::size_t>(n)}, [&](const proto::FrameView& view) {
            const auto message = proto::decode(view);
            if (!message) {
                return;
            }
            if (const auto* control = std::get_if<proto::Control>(&*message);
                control != nullptr && control->mode == proto::ControlMode::kSpeed) {
                const bool moving = control->speed != proto::Axes{};
                control_.push_back({t, moving});
                ++(moving ? speeds_seen_ : stops_seen_);
            }
        });
    }
}

}  // namespace gport::bench
