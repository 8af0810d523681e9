// Runs an ipc::Server with a FakeApi on its own io thread, on a socket in a
// fresh temporary directory. Test code touches the server and the fake only
// through on_io(), which runs on the io thread and waits for the result.
#pragma once

#include <spdlog/sinks/null_sink.h>
#include <spdlog/spdlog.h>
#include <stdlib.h>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <filesystem>
#include <future>
#include <memory>
#include <thread>

#include "fake_api.hpp"
#include "gport/ipc/server.hpp"

namespace gport::testing {

inline std::string make_temp_dir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "gport-ipc-XXXXXX").string();
    return ::mkdtemp(pattern.data());
}

inline std::shared_ptr<spdlog::logger> quiet_logger() {
    return std::make_shared<spdlog::logger>("test",
                                            std::make_shared<spdlog::sinks::null_sink_st>());
}

class ServerHarness {
  public:
    explicit ServerHarness(config::SocketConfig config = {},
                           std::shared_ptr<spdlog::logger> log = quiet_logger())
        : dir_(make_temp_dir()) {
        config.path = dir_ + "/gportd.sock";
        config_ = config;
        api.defer = [this](std::function<void()> run) { boost::asio::post(io_, std::move(run)); };
        server = std::make_unique<ipc::Server>(io_, api, config_, std::move(log));
        server->start();
        thread_ = std::thread([this] { io_.run(); });
    }

    ~ServerHarness() {
        stop();
        std::filesystem::remove_all(dir_);
    }

    // Closes the server and lets io.run() return by itself.
    void stop() {
        if (!thread_.joinable()) {
            return;
        }
        on_io([this] { server->close(); });
        work_.reset();
        thread_.join();
    }

    template <typename F>
    auto on_io(F f) -> decltype(f()) {
        std::packaged_task<decltype(f())()> task(std::move(f));
        auto result = task.get_future();
        boost::asio::post(io_, [&task] { task(); });
        return result.get();
    }

    // Polls `condition` on the io thread until it holds or ~10 s pass.
    template <typename F>
    bool eventually(F condition) {
        for (int i = 0; i < 1000; ++i) {
            if (on_io(condition)) {
                return true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }

    const std::string& path() const { return config_.path; }
    const std::string& dir() const { return dir_; }
    boost::asio::io_context& io() { return io_; }

  private:
    // Declared before the server so that they outlive it.
    std::string dir_;
    config::SocketConfig config_;
    boost::asio::io_context io_;
    boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work_{
        io_.get_executor()};

  public:
    FakeApi api;
    std::unique_ptr<ipc::Server> server;

  private:
    std::thread thread_;
};

}  // namespace gport::testing
