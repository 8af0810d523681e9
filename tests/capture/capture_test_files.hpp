// What the capture writer's and reader's tests share: a state directory of
// the test's own, capture lines and a logger whose lines the test can read.
#pragma once

#include <gtest/gtest.h>
#include <spdlog/logger.h>
#include <spdlog/sinks/ostream_sink.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "gport/capture/capture_writer.hpp"
#include "process.hpp"

namespace gport::capture::test {

inline std::string capture(std::uint64_t index, std::size_t pad = 0) {
    return nlohmann::json{{"index", index}, {"kind", "photo"}, {"pad", std::string(pad, 'x')}}
        .dump();
}

inline std::vector<std::string> lines_of(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> out;
    for (std::string line; std::getline(in, line);) {
        out.push_back(line);
    }
    return out;
}

// A logger into a string stream (thread-safe sink), shared with the test.
struct LogText {
    std::shared_ptr<std::ostringstream> text = std::make_shared<std::ostringstream>();
    std::shared_ptr<spdlog::logger> logger = std::make_shared<spdlog::logger>(
        "test", std::make_shared<spdlog::sinks::ostream_sink_mt>(*text));
    std::string str() const {
        logger->flush();
        return text->str();
    }
};

class CaptureFilesTest : public ::testing::Test {
  protected:
    CaptureFilesTest() { std::filesystem::create_directory(files_.dir); }
    void write_file(int n, const std::vector<std::string>& lines) const {
        std::ofstream out(files_.file(n));
        for (const auto& line : lines) {
            out << line << '\n';
        }
    }

    testing::TempDir tmp_;
    CaptureFiles files_{tmp_.file("state"), 1048576, 4};
    LogText log_;
};

}  // namespace gport::capture::test
