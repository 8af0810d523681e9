#include "checks.hpp"

#include <fmt/format.h>
#include <sys/un.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>

#include "gport/contract/names.hpp"

namespace gport::config::detail {
namespace {

constexpr std::array<std::string_view, 7> kLogLevels = {"trace", "debug",    "info", "warn",
                                                        "error", "critical", "off"};

// Longest path a sockaddr_un can hold, leaving room for the terminating NUL.
constexpr std::size_t kMaxSocketPath = sizeof(sockaddr_un::sun_path) - 1;

// Values are echoed in messages; past this length they are cut short.
constexpr std::size_t kMaxQuoted = 64;

std::optional<std::string> check_absolute_path(std::string_view path, std::string_view example) {
    if (path.empty()) {
        return fmt::format("must be an absolute path such as {}, got an empty string", example);
    }
    if (path.find('\0') != std::string_view::npos) {
        return fmt::format("must not contain a NUL character, got {}", json_quoted(path));
    }
    if (path.front() != '/') {
        return fmt::format("must be an absolute path such as {}, got {}", example,
                           json_quoted(path));
    }
    return std::nullopt;
}

}  // namespace

std::string_view log_levels_text() {
    return "trace, debug, info, warn, error, critical, off";
}

std::optional<std::string> check_log_level(std::string_view level) {
    if (std::find(kLogLevels.begin(), kLogLevels.end(), level) != kLogLevels.end()) {
        return std::nullopt;
    }
    return fmt::format("must be one of {}, got {}", log_levels_text(), json_quoted(level));
}

std::optional<std::string> check_state_dir(std::string_view path) {
    return check_absolute_path(path, "/var/lib/gportd");
}

std::optional<std::string> check_device_path(std::string_view path) {
    return check_absolute_path(path, "/dev/ttyUSB0");
}

std::optional<std::string> check_socket_path(std::string_view path) {
    if (auto problem = check_absolute_path(path, contract::kDefaultSocket)) {
        return problem;
    }
    if (path.size() > kMaxSocketPath) {
        return fmt::format(
            "must be at most {} bytes long (the limit of a Unix socket address), "
            "got {} bytes",
            kMaxSocketPath, path.size());
    }
    return std::nullopt;
}

std::string json_quoted(std::string_view text) {
    const bool cut = text.size() > kMaxQuoted;
    const nlohmann::json literal = std::string(text.substr(0, kMaxQuoted));
    // replace: bytes that are not UTF-8 (argv may hold anything) print as U+FFFD.
    std::string out = literal.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (cut) {
        out += "...";
    }
    return out;
}

}  // namespace gport::config::detail
