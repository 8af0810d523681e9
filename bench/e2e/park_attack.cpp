#include "park_attack.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "gport/base/descriptors.hpp"
#include "gport/base/futex.hpp"

extern char** environ;

namespace gport::bench {
namespace {

constexpr std::string_view kParkOpen = R"({"jsonrpc":"2.0","id":1,"method":"attitude_channel"})"
                                       "\n";
constexpr std::size_t kVersion1WordOffset = 24;  // the ring header's futex word in version 1
constexpr std::size_t kWakeWordOffset = 16;      // in a version 2 wake block
constexpr std::size_t kStack = 64 * 1024;        // thousands of threads: small stacks

struct ParkChannel {
    nlohmann::json result;
    std::deque<int> fds;
};

// Sends attitude_channel on `socket` and reads the reply and its descriptors.
ParkChannel ask_channel(int socket) {
    if (!write_all(socket, kParkOpen)) {
        throw std::runtime_error("park: cannot send attitude_channel");
    }
    ParkChannel c;
    std::string text;
    const auto deadline = now_ns() + 10'000'000'000LL;
    while (text.find('\n') == std::string::npos) {
        char data[4096];
        const auto n = base::receive_with_descriptors(socket, data, sizeof(data), c.fds);
        if (n < 0 && (errno == EAGAIN || errno == EINTR) && now_ns() < deadline) {
            ::usleep(1000);
            continue;
        }
        if (n <= 0) {
            throw std::runtime_error("park: no reply to attitude_channel");
        }
        text.append(data, static_cast<std::size_t>(n));
    }
    const auto reply = nlohmann::json::parse(text.substr(0, text.find('\n')));
    if (!reply.contains("result")) {
        throw std::runtime_error("park: attitude_channel refused: " + reply.dump());
    }
    c.result = reply["result"];
    return c;
}

const std::atomic<std::uint32_t>* word_of(int fd, std::size_t size, std::size_t offset) {
    void* memory = ::mmap(nullptr, size, PROT_READ, MAP_SHARED, fd, 0);
    if (memory == MAP_FAILED) {
        throw std::runtime_error(std::string("park: mmap: ") + std::strerror(errno));
    }
    return reinterpret_cast<const std::atomic<std::uint32_t>*>(static_cast<char*>(memory) + offset);
}

void* park_thread(void* word) {
    const auto& w = *static_cast<const std::atomic<std::uint32_t>*>(word);
    for (;;) {
        base::futex_wait(w, w.load(std::memory_order_acquire), std::chrono::seconds(60));
    }
    return nullptr;
}

}  // namespace

int park_child_main(int argc, char** argv) {
    if (argc < 4) {
        return 64;
    }
    const std::string socket = argv[0];
    const int threads = std::atoi(argv[1]);
    const bool gone = std::atoi(argv[2]) != 0;
    const int report = std::atoi(argv[3]);
    try {
        Fd connection = connect_unix(socket);
        auto channel = ask_channel(connection.get());
        const int version = channel.result.value("version", 0);
        const auto size = channel.result.at("size").get<std::size_t>();
        const int ring = base::take_descriptor(channel.fds);
        const int wake = base::take_descriptor(channel.fds);
        const auto* word = version >= 2 ? word_of(wake, 64, kWakeWordOffset)
                                        : word_of(ring, size, kVersion1WordOffset);
        pthread_attr_t attr;
        ::pthread_attr_init(&attr);
        ::pthread_attr_setstacksize(&attr, kStack);
        for (int i = 0; i < threads; ++i) {
            pthread_t thread;
            if (::pthread_create(&thread, &attr, park_thread,
                                 const_cast<std::atomic<std::uint32_t>*>(word)) != 0) {
                throw std::runtime_error("park: pthread_create failed after " + std::to_string(i) +
                                         " threads");
            }
        }
        ::usleep(200'000);  // let the last ones reach FUTEX_WAIT
        if (gone) {
            connection.reset();  // disconnects; the threads stay parked on the mapping
        }
        const std::string line = "parked " + std::to_string(version) + "\n";
        [[maybe_unused]] const auto n = ::write(report, line.data(), line.size());  // a pipe
        ::close(report);
        for (;;) {
            ::pause();
        }
    } catch (const std::exception& e) {
        const std::string line = std::string("error ") + e.what() + "\n";
        [[maybe_unused]] const auto n = ::write(report, line.data(), line.size());
        return 1;
    }
}

ParkAttack::ParkAttack(const std::string& socket, int threads, bool gone)
    : threads_(threads), gone_(gone) {
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
        throw std::runtime_error("park: pipe failed");
    }
    Fd read_end(pipe_fds[0]);
    posix_spawn_file_actions_t actions;
    ::posix_spawn_file_actions_init(&actions);
    ::posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 3);
    const std::string count = std::to_string(threads);
    std::vector<std::string> args = {"bench_e2e", "--park-child",   socket,
                                     count,       gone ? "1" : "0", "3"};
    std::vector<char*> argv;
    for (auto& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    const int rc =
        ::posix_spawn(&child_, "/proc/self/exe", &actions, nullptr, argv.data(), environ);
    ::posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[1]);
    if (rc != 0) {
        throw std::runtime_error(std::string("park: cannot start the peer: ") + std::strerror(rc));
    }
    std::string pending;
    std::string line;
    if (!read_line(read_end.get(), pending, line, 120'000) || line.rfind("parked ", 0) != 0) {
        stop();
        throw std::runtime_error("park: the peer did not park its threads: " + line);
    }
    version_ = std::atoi(line.c_str() + 7);
    if (gone) {
        holder_ = connect_unix(socket);
        auto channel = ask_channel(holder_.get());
        base::close_descriptors(channel.fds);
    }
}

ParkAttack::~ParkAttack() {
    stop();
}

void ParkAttack::stop() {
    if (child_ > 0) {
        ::kill(child_, SIGKILL);
        int status = 0;
        ::waitpid(child_, &status, 0);
        child_ = -1;
    }
    holder_.reset();
}

}  // namespace gport::bench
