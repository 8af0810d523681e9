#include "gport/config/loader.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

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
};

FileText read_file(const std::string& path) {
    FileText result;
    // "e": close-on-exec, so that no child of the daemon inherits the descriptor.
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rbe"),
                                                         &std::fclose);
    if (!file) {
        result.error = errno;
        return result;
    }
    // Read one byte past the limit to tell "exactly the limit" from "larger".
    result.text.resize(kMaxConfigBytes + 1);
    const auto got = std::fread(result.text.data(), 1, result.text.size(), file.get());
    if (std::ferror(file.get()) != 0) {
        result.error = errno != 0 ? errno : EIO;
        return result;
    }
    result.too_large = got > kMaxConfigBytes;
    result.text.resize(got);
    return result;
}

Errors file_errors(const std::string& path, const FileText& file) {
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
Result<Config> apply_command_line(Config config, const CommandLine& command_line) {
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
    if (file.error != 0 || file.too_large) {
        return file_errors(path, file);
    }
    return load_config_text(file.text, path);
}

Result<Config> load_config(const CommandLine& command_line, std::string_view default_path) {
    const bool given = command_line.config_path.has_value();
    const std::string path = given ? *command_line.config_path : std::string(default_path);
    const auto file = read_file(path);
    if (!given && file.error == ENOENT) {
        return apply_command_line(Config{}, command_line);  // no file: built-in defaults
    }
    if (file.error != 0 || file.too_large) {
        return file_errors(path, file);
    }
    auto loaded = load_config_text(file.text, path);
    if (!loaded) {
        return loaded;
    }
    return apply_command_line(std::move(loaded).value(), command_line);
}

}  // namespace gport::config
