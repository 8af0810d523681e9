#include "gport/daemon/serial_candidates.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <system_error>

namespace gport::daemon {
namespace {

namespace fs = std::filesystem;

// NAME's number after `prefix` (ttyUSB12 -> 12), or -1 when NAME is not
// `prefix` followed by digits only.
long number_after(std::string_view name, std::string_view prefix) {
    if (name.size() <= prefix.size() || name.substr(0, prefix.size()) != prefix) {
        return -1;
    }
    const auto digits = name.substr(prefix.size());
    if (digits.size() > 6 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return -1;
    }
    return std::strtol(std::string(digits).c_str(), nullptr, 10);
}

// ttySN has a UART behind it: the 8250 driver's `type` is not 0 (PORT_UNKNOWN).
bool has_uart(const std::string& sys, const std::string& name) {
    std::ifstream type(sys + "/class/tty/" + name + "/type");
    int value = 0;
    return type >> value && value != 0;
}

std::vector<std::pair<long, std::string>> numbered(const std::string& dev,
                                                   std::string_view prefix) {
    std::vector<std::pair<long, std::string>> found;
    std::error_code ec;
    for (fs::directory_iterator it(dev, ec), end; !ec && it != end; it.increment(ec)) {
        const auto name = it->path().filename().string();
        if (const long n = number_after(name, prefix); n >= 0) {
            found.emplace_back(n, name);
        }
    }
    std::sort(found.begin(), found.end());
    return found;
}

}  // namespace

std::vector<std::string> serial_candidates(const std::string& dev, const std::string& sys) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const char* alias : {"serial0", "serial1"}) {
        if (fs::exists(dev + "/" + alias, ec)) {
            out.push_back(dev + "/" + alias);
        }
    }
    constexpr std::array<std::string_view, 5> kKinds{"ttyAMA", "ttyTHS", "ttyUSB", "ttyACM",
                                                     "ttyS"};
    for (const auto kind : kKinds) {
        for (const auto& [n, name] : numbered(dev, kind)) {
            if (kind != "ttyS" || has_uart(sys, name)) {
                out.push_back(dev + "/" + name);
            }
        }
    }
    return out;
}

std::string candidates_hint(const std::vector<std::string>& candidates) {
    if (candidates.empty()) {
        return "no serial devices here (is the adapter plugged in? see `dmesg`)";
    }
    return fmt::format(
        "serial devices here: {}; set serial.device (or --device) to the gimbal's, or run "
        "`gportd --probe` to find it",
        fmt::join(candidates, ", "));
}

}  // namespace gport::daemon
