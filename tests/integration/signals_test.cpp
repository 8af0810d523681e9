// gportd and its signals, with the real gportd and gport-sim binaries:
// SIGHUP reloads the configuration without disturbing a motion, SIGQUIT
// stops like SIGTERM (zero speed on the wire, socket removed, exit 0), and
// a config path that is a FIFO is refused at once instead of hanging.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>

#include "harness.hpp"

namespace gport::testing {
namespace {

// gportd with its log on the Process's stdout (stderr redirected by a shell
// that execs it, so the pid is gportd's) and no --log-level, so that the
// config file's log.level is the one in effect.
class LoggedDaemon {
  public:
    LoggedDaemon(const TempDir& dir, const std::string& config, const std::string& device)
        : socket_(dir.file("gportd.sock")) {
        const std::string command = std::string("exec ") + GPORTD_PATH + " --config " + config +
                                    " --socket " + socket_ + " --device " + device + " 2>&1";
        process_ = std::make_unique<Process>(std::vector<std::string>{"/bin/sh", "-c", command});
    }
    const std::string& socket() const { return socket_; }
    Process& process() { return *process_; }
    // Waits for a log line containing `what`.
    bool logged(const std::string& what, std::chrono::milliseconds timeout = 10s) {
        return process_->wait_line([&](const std::string& l) { return contains(l, what); }, timeout)
            .has_value();
    }

  private:
    std::string socket_;
    std::unique_ptr<Process> process_;
};

void write_file(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::trunc) << text;
}

// A gimbal moving at yaw 20 deg/s for 30 s, commanded through a running gportd.
class MidMotion : public ::testing::Test {
  protected:
    void SetUp() override {
        write_file(config_, R"({"log": {"level": "info"}, "socket": {"max_clients": 16}})");
        daemon_ = std::make_unique<LoggedDaemon>(dir_, config_, sim_.link());
        client_ = std::make_unique<Client>(daemon_->socket());
        ASSERT_TRUE(client_->connected());
        ASSERT_TRUE(link_up(*client_));
        const auto reply = client_->call("speed", {{"yaw", 20}, {"duration_ms", 30000}});
        ASSERT_TRUE(reply.contains("result")) << reply.dump();
        ASSERT_TRUE(sim_.wait_speed({0, 0, 2000}));
    }

    // Speed frames the gimbal received since the last call: true when none
    // of them was a zero speed.
    bool no_zero_speed_since_last_look() {
        for (const auto& line : sim_.process().drain()) {
            const auto j = Json::parse(line, nullptr, false);
            if (j.is_object() && j.value("mode", "") == "speed" && j["speed"] == Json{0, 0, 0}) {
                return false;
            }
        }
        return true;
    }

    TempDir dir_;
    std::string config_ = dir_.file("gportd.json");
    SimProcess sim_{dir_};
    std::unique_ptr<LoggedDaemon> daemon_;
    std::unique_ptr<Client> client_;
};

TEST_F(MidMotion, SighupReloadsWithoutDisturbingTheMotion) {
    ASSERT_FALSE(daemon_->logged("connected: pid", 300ms)) << "debug lines before the reload";
    write_file(config_, R"({"log": {"level": "debug"}, "socket": {"max_clients": 12}})");
    daemon_->process().signal(SIGHUP);
    EXPECT_TRUE(daemon_->logged("socket.max_clients changed; it needs a restart"));
    EXPECT_TRUE(daemon_->logged("reloaded configuration from " + config_ +
                                ": 1 keys applied, 1 need a restart"));
    ASSERT_TRUE(daemon_->process().running()) << "SIGHUP killed gportd";
    // The log level applies at once: a new client's connection is a debug line.
    Client second(daemon_->socket());
    ASSERT_TRUE(second.connected());
    EXPECT_TRUE(daemon_->logged("connected: pid"));
    // The motion goes on: still reported, still re-sent, never stopped.
    const auto status = client_->call("status");
    EXPECT_EQ(status["result"]["motion"]["mode"], "speed") << status.dump();
    EXPECT_TRUE(sim_.wait_speed({0, 0, 2000})) << "keepalive frames stopped after SIGHUP";
    EXPECT_TRUE(no_zero_speed_since_last_look()) << "SIGHUP sent a zero speed";
}

TEST_F(MidMotion, SighupWithABadConfigKeepsTheOldOne) {
    write_file(config_, R"({"log": {"level": "loud"}})");
    daemon_->process().signal(SIGHUP);
    EXPECT_TRUE(daemon_->logged("log.level: must be one of"));
    EXPECT_TRUE(daemon_->logged("configuration not reloaded: 1 error(s) in " + config_ +
                                "; still running on the previous configuration"));
    ASSERT_TRUE(daemon_->process().running());
    EXPECT_TRUE(client_->call("status").contains("result"));
    EXPECT_TRUE(sim_.wait_speed({0, 0, 2000}));
    EXPECT_TRUE(no_zero_speed_since_last_look());
    // A second SIGHUP once the file is fixed applies it.
    write_file(config_, R"({"log": {"level": "info"}, "socket": {"max_clients": 16}})");
    daemon_->process().signal(SIGHUP);
    EXPECT_TRUE(daemon_->logged("0 keys applied, 0 need a restart"));
}

TEST_F(MidMotion, SigquitStopsTheGimbalRemovesTheSocketAndExitsZero) {
    struct stat st {};
    ASSERT_EQ(::stat(daemon_->socket().c_str(), &st), 0);
    daemon_->process().signal(SIGQUIT);
    EXPECT_TRUE(sim_.wait_speed({0, 0, 0})) << "no zero-speed frame after SIGQUIT";
    EXPECT_EQ(daemon_->process().wait(), 0);
    EXPECT_NE(::stat(daemon_->socket().c_str(), &st), 0) << "socket file left behind";
}

TEST_F(MidMotion, SigintStopsTheGimbalAndRemovesTheSocket) {
    daemon_->process().signal(SIGINT);
    EXPECT_TRUE(sim_.wait_speed({0, 0, 0})) << "no zero-speed frame after SIGINT";
    EXPECT_EQ(daemon_->process().wait(), 0);
    struct stat st {};
    EXPECT_NE(::stat(daemon_->socket().c_str(), &st), 0) << "socket file left behind";
}

TEST(ConfigPath, AFifoExits78WithoutWaitingForAWriter) {
    TempDir dir;
    const auto fifo = dir.file("gportd.json");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    Process p({"/bin/sh", "-c",
               std::string("exec ") + GPORTD_PATH + " --config " + fifo + " --device " +
                   dir.file("never-opened") + " 2>&1"});
    EXPECT_TRUE(p.wait_line([](const std::string& l) {
        return contains(l, "it is a FIFO; a regular file is needed");
    }));
    EXPECT_EQ(p.wait(), 78) << "gportd hangs on a FIFO config path";
}

}  // namespace
}  // namespace gport::testing
