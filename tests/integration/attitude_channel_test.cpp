// The shared-memory attitude channel end to end: the real gportd on
// gport-sim, clients that receive the ring and their connection's wake
// block with recvmsg and map them read-only (docs/api.md, "Shared-memory
// attitude channel"); and the attacks: threads parked on a word, by a
// connection that stays or one that left, and descriptors asked for in
// batches by a peer that never reads.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <thread>
#include <vector>

#include "channel_client.hpp"
#include "gport/base/futex.hpp"
#include "sim_daemon_fixture.hpp"

namespace gport::testing {
namespace {

constexpr std::size_t kBytes = base::ring_bytes(64);

std::size_t open_descriptors(pid_t pid) {
    std::size_t count = 0;
    for ([[maybe_unused]] const auto& entry :
         std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
        ++count;
    }
    return count;
}

// Sends one request line on `fd` and reads the reply with plain read(2).
std::string plain_call(int fd, const std::string& request) {
    const std::string line = request + "\n";
    if (::write(fd, line.data(), line.size()) != static_cast<ssize_t>(line.size())) {
        return {};
    }
    std::string reply;
    char byte = 0;
    while (::read(fd, &byte, 1) == 1 && byte != '\n') {
        reply += byte;
    }
    return reply;
}

// A connection's channel: the ring and its own wake block.
struct Channel {
    std::unique_ptr<RingMapping> ring;
    std::unique_ptr<WakeMapping> wake;
    const base::RingReader reader() const { return ring->reader(); }
    const std::atomic<std::uint32_t>& word() const { return wake->word(); }
};

// Opens the channel on `client` and maps it; the descriptors are closed.
Channel open_channel(DescriptorClient& client) {
    const auto reply = client.call("attitude_channel");
    EXPECT_TRUE(reply.contains("result")) << reply;
    EXPECT_EQ(reply["result"]["descriptors"], 2) << reply;
    const int ring = client.take_descriptor();
    const int wake = client.take_descriptor();
    EXPECT_GE(ring, 0);
    EXPECT_GE(wake, 0);
    Channel c{std::make_unique<RingMapping>(ring, kBytes), std::make_unique<WakeMapping>(wake)};
    ::close(ring);
    ::close(wake);
    return c;
}

// Takes samples in order, waiting on the futex, until `stop` or closed.
struct RingFollower {
    explicit RingFollower(const Channel& channel)
        : reader_(channel.reader()), word_(channel.word()) {
        thread_ = std::thread([this] { run(); });
    }
    ~RingFollower() { finish(); }
    void finish() {
        stop = true;
        if (thread_.joinable()) {
            thread_.join();
        }
    }
    void run() {
        std::uint64_t cursor = 0;
        while (!stop) {
            const auto seen = word_.load();
            bool took = false;
            while (auto sample = reader_.next(cursor, missed)) {
                samples.push_back(*sample);
                took = true;
            }
            if (reader_.closed()) {
                closed_seen = true;
                return;
            }
            if (!took && base::futex_wait(word_, seen, std::chrono::milliseconds(200)) ==
                             base::FutexWait::kWoken) {
                ++woken;
            }
        }
    }

    base::RingReader reader_;
    const std::atomic<std::uint32_t>& word_;
    std::atomic<bool> stop{false};
    std::vector<base::RingSample> samples;
    std::uint64_t missed = 0;
    std::atomic<int> woken{0};
    std::atomic<bool> closed_seen{false};
    std::thread thread_;
};

class AttitudeChannelTest : public SimDaemonTest {
  protected:
    std::string config_extra() const override {
        return R"("socket": {"max_clients_per_uid": 256, "max_clients": 256, "max_requests_per_s": 100000})";
    }
    pid_t daemon_pid() { return daemon_->process().pid(); }
};

TEST_F(AttitudeChannelTest, SamplesArriveInOrderAsTheSocketSendsThemAndWakeTheReader) {
    DescriptorClient reader(daemon_->socket());
    auto channel = open_channel(reader);
    auto& ring = channel.ring;
    ASSERT_TRUE(ring->mapped());
    ASSERT_EQ(ring->check(), std::nullopt);
    ASSERT_EQ(channel.wake->check(), std::nullopt);
    RingFollower follower(channel);
    ASSERT_EQ(client_->call("subscribe", {{"topics", {"attitude"}}})["result"]["topics"].size(),
              1u);
    std::map<std::uint64_t, Json> socket_samples;
    while (socket_samples.size() < 30) {
        auto note = client_->notification("attitude");
        ASSERT_TRUE(note);
        socket_samples[(*note)["params"]["seq"].get<std::uint64_t>()] = (*note)["params"];
    }
    ASSERT_TRUE(eventually([&] {
        return ring->reader().published() > 0 &&
               ring->reader().latest()->seq >= socket_samples.rbegin()->first;
    }));
    follower.finish();
    ASSERT_GE(follower.samples.size(), 20u);
    EXPECT_EQ(follower.missed, 0u);
    EXPECT_GT(follower.woken.load(), 0);
    std::size_t matched = 0;
    for (std::size_t i = 0; i < follower.samples.size(); ++i) {
        const auto& s = follower.samples[i];
        if (i > 0) {
            EXPECT_EQ(s.seq, follower.samples[i - 1].seq + 1);
        }
        auto it = socket_samples.find(s.seq);
        if (it == socket_samples.end()) {
            continue;
        }
        ++matched;
        const Json& j = it->second;
        EXPECT_EQ(s.t, j["t"].get<double>());
        EXPECT_EQ(s.imu[0], j["imu"]["roll"].get<double>());
        EXPECT_EQ(s.imu[1], j["imu"]["pitch"].get<double>());
        EXPECT_EQ(s.hall[2], j["hall"]["yaw"].get<double>());
        EXPECT_EQ(s.has_rates, j.contains("rates"));
    }
    EXPECT_GE(matched, 20u);
}

TEST_F(AttitudeChannelTest, TheSealsLeaveOnlyReadOnlyMappings) {
    DescriptorClient reader(daemon_->socket());
    ASSERT_TRUE(reader.call("attitude_channel").contains("result"));
    const int fd = reader.take_descriptor();
    const int wake_fd = reader.take_descriptor();
    ASSERT_GE(fd, 0);
    ASSERT_GE(wake_fd, 0);
    const int seals = F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL;
    EXPECT_EQ(::fcntl(fd, F_GET_SEALS), seals);
    EXPECT_EQ(::fcntl(wake_fd, F_GET_SEALS), seals);
    EXPECT_NE(::fcntl(wake_fd, F_GETFD) & FD_CLOEXEC, 0);
    EXPECT_EQ(::mmap(nullptr, 64, PROT_READ | PROT_WRITE, MAP_SHARED, wake_fd, 0), MAP_FAILED);
    EXPECT_EQ(::ftruncate(wake_fd, 0), -1);
    ::close(wake_fd);
    EXPECT_NE(::fcntl(fd, F_GETFD) & FD_CLOEXEC, 0);  // MSG_CMSG_CLOEXEC
    const char byte = 'x';
    EXPECT_EQ(::pwrite(fd, &byte, 1, 0), -1);
    EXPECT_EQ(errno, EPERM);
    EXPECT_EQ(::ftruncate(fd, 0), -1);
    EXPECT_EQ(::ftruncate(fd, 1 << 20), -1);
    EXPECT_EQ(::fallocate(fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, 0, 4096), -1);
    EXPECT_EQ(::fcntl(fd, F_ADD_SEALS, F_SEAL_WRITE), -1);
    EXPECT_EQ(::mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0), MAP_FAILED);
    void* ro = ::mmap(nullptr, kBytes, PROT_READ, MAP_SHARED, fd, 0);
    ASSERT_NE(ro, MAP_FAILED);
    EXPECT_EQ(::mprotect(ro, kBytes, PROT_READ | PROT_WRITE), -1);
    struct stat info {};
    ASSERT_EQ(::fstat(fd, &info), 0);
    EXPECT_EQ(static_cast<std::size_t>(info.st_size), kBytes);
    EXPECT_EQ(base::RingReader::check(ro, kBytes), std::nullopt);
    ::munmap(ro, kBytes);
    ::close(fd);
    // Samples still arrive: nothing the client tried reached the daemon's block.
    DescriptorClient again(daemon_->socket());
    auto channel = open_channel(again);
    const auto before = channel.reader().published();
    EXPECT_TRUE(eventually([&] { return channel.reader().published() > before; }));
}

TEST_F(AttitudeChannelTest, AClientReadingWithPlainReadLosesOnlyTheDescriptor) {
    const auto baseline = open_descriptors(daemon_pid());
    const auto mine = open_descriptors(::getpid());
    {
        DescriptorClient plain(daemon_->socket());  // its socket, read with read(2) here
        ASSERT_TRUE(plain.connected());
        const auto reply = plain_call(plain.socket(), R"({"id":1,"method":"attitude_channel"})");
        EXPECT_NE(reply.find("\"slots\":64"), std::string::npos) << reply;
        EXPECT_NE(plain_call(plain.socket(), R"({"id":2,"method":"status"})")
                      .find("\"attitude_channel\":true"),
                  std::string::npos);
        EXPECT_EQ(open_descriptors(::getpid()), mine + 1);  // its socket only
    }
    EXPECT_TRUE(eventually(
        [&] { return client_->call("status")["result"]["attitude_channel_clients"] == 0; }));
    // At most the ring's memfd and the waker thread's eventfd.
    EXPECT_LE(open_descriptors(daemon_pid()), baseline + 2);
}

// A client that asks for the channel between many replies and does not read:
// its socket fills, the descriptor's line waits for room, nobody else waits.
TEST_F(AttitudeChannelTest, AClientThatNeverReadsItsSocketHurtsNobody) {
    DescriptorClient stuck(daemon_->socket());
    auto stuck_channel = open_channel(stuck);
    std::string flood;
    const auto add = [&flood](int id, const char* method) {
        flood += R"({"id":)" + std::to_string(id) + R"(,"method":")" + method + "\"}\n";
    };
    for (int id = 100; id < 400; ++id) {
        add(id, id % 2 == 1 ? "attitude_channel" : "status");
    }
    ASSERT_TRUE(stuck.send(flood));
    DescriptorClient reader(daemon_->socket());
    auto channel = open_channel(reader);
    RingFollower follower(channel);
    client_->call("subscribe", {{"topics", {"attitude"}}});
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(client_->notification("attitude"));
    }
    ASSERT_TRUE(eventually([&] { return follower.woken.load() > 5; }));
    EXPECT_TRUE(client_->call("status")["result"].is_object());
    follower.finish();
    EXPECT_EQ(follower.missed, 0u);
    EXPECT_GT(stuck_channel.reader().published(), 0u);  // the same block
    // Now it reads, slowly: every reply in order, and no descriptor: the
    // connection has its channel already ("descriptors":0).
    stuck.read_chunk(300);
    int expected = 100;
    while (expected < 400) {
        auto line = stuck.next();
        ASSERT_TRUE(line) << "no reply " << expected;
        ASSERT_EQ((*line)["id"], expected);
        ASSERT_TRUE(line->contains("result")) << *line;
        if (expected % 2 == 1) {
            EXPECT_EQ((*line)["result"]["descriptors"], 0) << *line;
        }
        ++expected;
    }
    EXPECT_EQ(stuck.descriptors(), 0u);
}

TEST_F(AttitudeChannelTest, StatusCountsTheClientsThatOpenedIt) {
    EXPECT_EQ(client_->call("status")["result"]["client"]["attitude_channel"], false);
    {
        DescriptorClient reader(daemon_->socket());
        open_channel(reader);
        const auto status = reader.call("status")["result"];
        EXPECT_EQ(status["client"]["attitude_channel"], true);
        EXPECT_EQ(status["attitude_channel_clients"], 1);
    }
    EXPECT_TRUE(eventually(
        [&] { return client_->call("status")["result"]["attitude_channel_clients"] == 0; }));
}

TEST_F(AttitudeChannelTest, ShutdownSetsClosedAndWakesAWaiter) {
    DescriptorClient reader(daemon_->socket());
    auto channel = open_channel(reader);
    RingFollower follower(channel);
    ASSERT_TRUE(eventually([&] { return follower.woken.load() > 0; }));
    daemon_->process().signal(SIGTERM);
    ASSERT_TRUE(daemon_->process().wait());
    EXPECT_TRUE(eventually([&] { return follower.closed_seen.load(); }));
    EXPECT_TRUE(channel.reader().closed());
    EXPECT_GT(channel.reader().published(), 0u);  // the mapping outlives the daemon
}

TEST_F(AttitudeChannelTest, AHundredClientsShareOneBlock) {
    const auto baseline = open_descriptors(daemon_pid());
    std::vector<std::unique_ptr<DescriptorClient>> clients;
    std::set<ino_t> blocks;
    std::set<ino_t> wakes;
    for (int i = 0; i < 100; ++i) {
        clients.push_back(std::make_unique<DescriptorClient>(daemon_->socket()));
        ASSERT_TRUE(clients.back()->call("attitude_channel").contains("result"));
        const int fd = clients.back()->take_descriptor();
        const int wake = clients.back()->take_descriptor();
        ASSERT_GE(fd, 0);
        ASSERT_GE(wake, 0);
        struct stat info {};
        ASSERT_EQ(::fstat(fd, &info), 0);
        blocks.insert(info.st_ino);
        ASSERT_EQ(::fstat(wake, &info), 0);
        wakes.insert(info.st_ino);
        ::close(fd);
        ::close(wake);
    }
    EXPECT_EQ(blocks.size(), 1u);   // one ring for all
    EXPECT_EQ(wakes.size(), 100u);  // a wake block each
    EXPECT_EQ(client_->call("status")["result"]["attitude_channel_clients"], 100);
    // One socket per client, the ring's memfd and the waker's eventfd:
    // gportd keeps only the mapping of each wake block once it was sent.
    EXPECT_LE(open_descriptors(daemon_pid()), baseline + 100 + 2);
}

}  // namespace
}  // namespace gport::testing
