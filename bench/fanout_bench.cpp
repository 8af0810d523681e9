// fanout_bench: what one frame's fan-out to N Unix stream sockets costs the
// writer, sent as N sendmsg() calls (what gportd does) or as N
// IORING_OP_SEND entries given to the kernel with one io_uring_submit().
// One epoll thread reads every socket, as N subscribers would. It alternates
// the two ways in the same run and prints the writer's CPU per send (user and
// system together), measured as the process's CPU minus the reader thread's (io_uring's
// kernel workers are threads of the process, so their time counts for the
// writer). docs/performance.md, "io_uring batching (measured, not adopted)".
//
//   fanout_bench [--seconds S] [--pairs P]
#include <liburing.h>
#include <pthread.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace {

// An attitude notification about as long as gportd's (214 bytes).
const std::string kLine =
    R"({"jsonrpc":"2.0","method":"attitude","params":{"imu":{"roll":1.23,"pitch":-4.56,)"
    R"("yaw":78.9},"hall":{"roll":-19.21,"pitch":-0.16,"yaw":4.66},"rates":null,)"
    R"("t":"2026-11-23T04:30:00.123456Z","seq":123456,"dropped":0}})"
    "\n";

std::int64_t now_ns() {
    timespec t{};
    ::clock_gettime(CLOCK_MONOTONIC, &t);
    return std::int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec;
}

// CPU seconds on a CPU-time clock (a thread's or the process's).
double cpu_seconds(clockid_t clock) {
    timespec t{};
    ::clock_gettime(clock, &t);
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) / 1e9;
}

void fail(const std::string& what) {
    throw std::runtime_error(what + ": " + std::strerror(errno));
}

// N socket pairs: the writer keeps [i].first, the reader [i].second.
class Sockets {
  public:
    explicit Sockets(int n) {
        for (int i = 0; i < n; ++i) {
            int fds[2];
            if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0, fds) != 0) {
                fail("socketpair");
            }
            pairs_.emplace_back(fds[0], fds[1]);
        }
    }
    ~Sockets() {
        for (const auto& [a, b] : pairs_) {
            ::close(a);
            ::close(b);
        }
    }
    Sockets(const Sockets&) = delete;
    Sockets& operator=(const Sockets&) = delete;

    const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }

  private:
    std::vector<std::pair<int, int>> pairs_;
};

// One epoll thread that drains every reader socket.
class Reader {
  public:
    explicit Reader(const Sockets& sockets) : epoll_(::epoll_create1(EPOLL_CLOEXEC)) {
        for (const auto& pair : sockets.pairs()) {
            epoll_event e{};
            e.events = EPOLLIN;
            e.data.fd = pair.second;
            ::epoll_ctl(epoll_, EPOLL_CTL_ADD, pair.second, &e);
        }
        thread_ = std::thread([this] { run(); });
    }
    ~Reader() {
        running_ = false;
        thread_.join();
        ::close(epoll_);
    }
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;

    // The reader thread's CPU seconds so far.
    double cpu() {
        clockid_t clock{};
        ::pthread_getcpuclockid(thread_.native_handle(), &clock);
        return cpu_seconds(clock);
    }

  private:
    void run() {
        epoll_event events[256];
        char buffer[65536];
        while (running_) {
            const int n = ::epoll_wait(epoll_, events, 256, 20);
            for (int i = 0; i < n; ++i) {
                ssize_t r = 0;
                while ((r = ::read(events[i].data.fd, buffer, sizeof(buffer))) > 0) {
                }
            }
        }
    }

    int epoll_;
    std::atomic<bool> running_{true};
    std::thread thread_;
};

// Sends one line to every socket with one sendmsg() each.
std::uint64_t send_each(const Sockets& sockets) {
    std::uint64_t failed = 0;
    for (const auto& pair : sockets.pairs()) {
        iovec iov{const_cast<char*>(kLine.data()), kLine.size()};
        msghdr m{};
        m.msg_iov = &iov;
        m.msg_iovlen = 1;
        if (::sendmsg(pair.first, &m, MSG_DONTWAIT | MSG_NOSIGNAL) !=
            static_cast<ssize_t>(kLine.size())) {
            ++failed;
        }
    }
    return failed;
}

class Ring {
  public:
    explicit Ring(unsigned entries) {
        if (const int rc = ::io_uring_queue_init(entries, &ring_, 0); rc < 0) {
            errno = -rc;
            fail("io_uring_queue_init");
        }
    }
    ~Ring() { ::io_uring_queue_exit(&ring_); }
    Ring(const Ring&) = delete;
    Ring& operator=(const Ring&) = delete;

    // One IORING_OP_SEND per socket, one submit, then every completion.
    std::uint64_t send_batch(const Sockets& sockets) {
        for (const auto& pair : sockets.pairs()) {
            io_uring_sqe* sqe = ::io_uring_get_sqe(&ring_);
            ::io_uring_prep_send(sqe, pair.first, kLine.data(), kLine.size(), MSG_NOSIGNAL);
        }
        ::io_uring_submit(&ring_);
        std::uint64_t failed = 0;
        for (std::size_t done = 0; done < sockets.pairs().size(); ++done) {
            io_uring_cqe* cqe = nullptr;
            if (::io_uring_wait_cqe(&ring_, &cqe) < 0) {
                return failed + sockets.pairs().size() - done;
            }
            failed += cqe->res != static_cast<int>(kLine.size()) ? 1 : 0;
            ::io_uring_cqe_seen(&ring_, cqe);
        }
        return failed;
    }

  private:
    io_uring ring_{};
};

// Per send, in µs: the writer's CPU (the process's minus the reader's, so
// that io_uring's kernel workers count), and the part of it that other
// threads than the writing one (io-wq workers) spent. getrusage's user and
// system split is sampled at the tick, too coarse here: the sends' cost is
// almost all system time (docs/performance.md, "Profile").
struct Trial {
    double writer_us = 0;
    double workers_us = 0;
    double reader_us = 0;
    double writer_core_percent = 0;
    std::uint64_t failed = 0;
};

// `rate` frames/s to `n` sockets for `seconds`, each frame sent by `send`.
template <typename Send>
Trial run_trial(int n, double rate, double seconds, Send&& send) {
    Sockets sockets(n);
    Reader reader(sockets);
    const auto period = static_cast<std::int64_t>(1e9 / rate);
    const auto frames = static_cast<std::int64_t>(rate * seconds);
    const auto process0 = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID);
    const auto writer0 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
    const auto reader0 = reader.cpu();
    const auto t0 = now_ns();
    Trial t;
    for (std::int64_t f = 0; f < frames; ++f) {
        const auto due = t0 + f * period;
        const timespec at{static_cast<time_t>(due / 1'000'000'000), due % 1'000'000'000};
        while (::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr) == EINTR) {
        }
        t.failed += send(sockets);
    }
    const double wall = static_cast<double>(now_ns() - t0) / 1e9;
    const auto writer1 = cpu_seconds(CLOCK_THREAD_CPUTIME_ID);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the reader catches up
    const auto process1 = cpu_seconds(CLOCK_PROCESS_CPUTIME_ID);
    const auto reader1 = reader.cpu();
    const double per_send = 1e6 / (static_cast<double>(frames) * n);
    const double thread = writer1 - writer0;
    t.reader_us = (reader1 - reader0) * per_send;
    t.writer_us = (process1 - process0) * per_send - t.reader_us;
    t.workers_us = t.writer_us - thread * per_send;
    t.writer_core_percent = t.writer_us / per_send / wall * 100;
    return t;
}

void print(const char* how, int n, double rate, int pair, const Trial& t) {
    std::printf(
        "%4d x %4.0f/s | pair %d | %-8s | writer %6.3f us/send (io-wq workers "
        "%5.3f) | %5.1f %% of a core | reader %5.3f us/send | failed %llu\n",
        n, rate, pair, how, t.writer_us, t.workers_us, t.writer_core_percent, t.reader_us,
        static_cast<unsigned long long>(t.failed));
    std::fflush(stdout);
}

void run_cell(int n, double rate, double seconds, int pairs) {
    Ring ring(256);
    double each = 0;
    double batch = 0;
    for (int p = 1; p <= pairs; ++p) {
        const auto a = run_trial(n, rate, seconds, send_each);
        print("sendmsg", n, rate, p, a);
        const auto b =
            run_trial(n, rate, seconds, [&](const Sockets& s) { return ring.send_batch(s); });
        print("io_uring", n, rate, p, b);
        each += a.writer_us;
        batch += b.writer_us;
    }
    std::printf("%4d x %4.0f/s | io_uring / sendmsg writer CPU per send: %.2f\n\n", n, rate,
                batch / each);
}

double number(const char* name, const char* text, double low, double high) {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || *end != '\0' || v < low || v > high) {
        std::fprintf(stderr, "fanout_bench: %s must be a number from %g to %g, not '%s'\n", name,
                     low, high, text);
        std::exit(64);
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    double seconds = 3;
    int pairs = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--seconds" && i + 1 < argc) {
            seconds = number("--seconds", argv[++i], 0.1, 600);
        } else if (arg == "--pairs" && i + 1 < argc) {
            pairs = static_cast<int>(number("--pairs", argv[++i], 1, 100));
        } else {
            std::fprintf(stderr,
                         "usage: fanout_bench [--seconds S (0.1-600, default 3)] "
                         "[--pairs P (1-100, default 3)]\n"
                         "Alternates N sendmsg() and one io_uring_submit of N sends per frame,\n"
                         "at 100 sockets x 500 frames/s and 50 x 50/s, S seconds per trial.\n");
            return arg == "-h" || arg == "--help" ? 0 : 64;
        }
    }
    // A kernel or container may refuse io_uring (ENOSYS, EPERM with
    // kernel.io_uring_disabled or a seccomp filter): nothing to compare.
    io_uring probe{};
    if (const int rc = ::io_uring_queue_init(8, &probe, 0); rc < 0) {
        std::fprintf(stderr, "fanout_bench: io_uring is not available here (%s); skipped\n",
                     std::strerror(-rc));
        return 77;
    }
    ::io_uring_queue_exit(&probe);
    try {
        run_cell(100, 500, seconds, pairs);
        run_cell(50, 50, seconds, pairs);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fanout_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
