#include "gport/config/loader.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "accounts.hpp"
#include "checks.hpp"
#include "parse.hpp"
#include "reader.hpp"
#include "sections.hpp"

namespace gport::config {
namespace {

struct FileText {
    std::string text;
    int error = 0;  // errno of the failed open or read; 0 when `text` is the whole file
    bool too_large = false;
    const char* not_regular = nullptr;  // what the path is, when not a regular file
};

const char* kind_of(mode_t mode) {
    switch (mode & S_IFMT) {
        case S_IFDIR:
            return "a directory";
        case S_IFIFO:
            return "a FIFO";
        case S_IFCHR:
            return "a character device";
        case S_IFBLK:
            return "a block device";
        case S_IFSOCK:
            return "a socket";
        default:
            return "not a regular file";
    }
}

// Reads up to the limit plus one byte, to tell "exactly the limit" from "larger".
void read_all(int fd, FileText& result) {
    result.text.resize(kMaxConfigBytes + 1);
    std::size_t got = 0;
    while (got < result.text.size()) {
        const auto n = ::read(fd, result.text.data() + got, result.text.size() - got);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0) {
            result.error = errno;
            return;
        }
        if (n == 0) {
            break;
        }
        got += static_cast<std::size_t>(n);
    }
    result.too_large = got > kMaxConfigBytes;
    result.text.resize(got);
}

FileText read_file(const std::string& path) {
    FileText result;
    // O_NONBLOCK: opening a FIFO would otherwise wait for a writer forever.
    // O_CLOEXEC: no child of the daemon inherits the descriptor.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        result.error = errno;
        return result;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        result.error = errno;
    } else if (!S_ISREG(st.st_mode)) {
        result.not_regular = kind_of(st.st_mode);
    } else {
        read_all(fd, result);  // O_NONBLOCK changes nothing for a regular file
    }
    ::close(fd);
    return result;
}

bool failed(const FileText& file) {
    return file.error != 0 || file.too_large || file.not_regular != nullptr;
}

Errors file_errors(const std::string& path, const FileText& file) {
    if (file.not_regular != nullptr) {
        return Errors{
            {fmt::format("{}: cannot read the config file: it is {}; a regular file "
                         "is needed",
                         path, file.not_regular)}};
    }
    if (file.too_large) {
        return Errors{
            {fmt::format("{}: the config file is larger than {} bytes; is this the "
                         "right file?",
                         path, kMaxConfigBytes)}};
    }
    return Errors{
        {fmt::format("{}: cannot read the config file: {}", path, std::strerror(file.error))}};
}

// Applies --device, --socket, --log-level and --simulate. parse_command_line()
// has already checked them; they are checked again because a CommandLine may
// also be built by code.
// access.vehicle_uids when the file does not set it: the packaged
// gport-mavlink's user where it exists, else nobody (but root and gportd's
// own user, who always may).
void resolve_vehicle_uids(Config& config) {
    if (config.access.vehicle_uids) {
        return;
    }
    config.access.vehicle_uids.emplace();
    if (auto uid = detail::lookup_user(kVehicleUser)) {
        config.access.vehicle_uids->push_back(*uid);
    }
}

Result<Config> apply_command_line(Config config, const CommandLine& command_line) {
    resolve_vehicle_uids(config);
    std::vector<std::string> errors;
    const auto apply = [&](const std::optional<std::string>& value, std::string_view option,
                           auto check, std::string& target) {
        if (!value) {
            return;
        }
        if (auto problem = check(*value)) {
            errors.push_back(fmt::format("{}: {}", option, *problem));
        } else {
            target = *value;
        }
    };
    apply(command_line.device, "--device", detail::check_device_path, config.serial.device);
    apply(command_line.socket_path, "--socket", detail::check_socket_path, config.socket.path);
    apply(command_line.log_level, "--log-level", detail::check_log_level, config.log.level);
    apply(command_line.state_dir, "--state-dir", detail::check_state_dir, config.captures.dir);
    config.simulate = command_line.simulate;
    if (!errors.empty()) {
        return Errors{std::move(errors)};
    }
    return config;
}

}  // namespace

Result<Config> load_config_text(std::string_view text, std::string_view origin) {
    detail::Reader reader(origin);
    Config config;
    if (auto root = detail::parse_json(text, reader)) {
        detail::read_config(reader, *root, config);
    }
    if (reader.error_count() != 0) {
        return reader.take_errors();
    }
    return config;
}

Result<Config> load_config_file(const std::string& path) {
    const auto file = read_file(path);
    if (failed(file)) {
        return file_errors(path, file);
    }
    return load_config_text(file.text, path);
}

Result<Config> load_config(const CommandLine& command_line) {
    return load_config(command_line, default_config_path());
}

Result<Config> load_config(const CommandLine& command_line, std::string_view default_path) {
    const bool given = command_line.config_path.has_value();
    const std::string path = given ? *command_line.config_path : std::string(default_path);
    const auto file = read_file(path);
    if (!given && file.error == ENOENT) {
        return apply_command_line(Config{}, command_line);  // no file: built-in defaults
    }
    if (failed(file)) {
        return file_errors(path, file);
    }
    auto loaded = load_config_text(file.text, path);
    if (!loaded) {
        return loaded;
    }
    return apply_command_line(std::move(loaded).value(), command_line);
}

}  // namespace gport::config
