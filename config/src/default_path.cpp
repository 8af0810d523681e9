// Where gportd looks for its configuration when --config is not given: the
// configuration directory of the prefix it was installed to, so that a
// `cmake --install --prefix ~/gport` tree reads ~/gport/etc/gportd/gportd.json
// (installed there) and the .deb's /usr/bin/gportd reads /etc/gportd/gportd.json.
#include <filesystem>
#include <system_error>

#include "gport/config/command_line.hpp"

namespace gport::config {
namespace {

namespace fs = std::filesystem;

// The prefix `program` was installed to: the directory holding `bindir`
// (relative to it) that holds the program; nothing if it is not in one.
std::optional<fs::path> installed_prefix(const fs::path& program, const fs::path& bindir) {
    const fs::path dir = program.parent_path();
    if (bindir.is_absolute()) {
        return std::nullopt;  // no prefix to derive: the forced paths decide
    }
    fs::path prefix = dir;
    for (auto part = bindir.end(); part != bindir.begin();) {
        --part;
        if (part->empty()) {
            continue;  // a trailing slash
        }
        if (prefix.filename() != *part) {
            return std::nullopt;
        }
        prefix = prefix.parent_path();
    }
    return prefix;
}

// GNUInstallDirs' mapping of SYSCONFDIR for a prefix.
fs::path sysconfdir_of(const fs::path& prefix, const fs::path& sysconfdir) {
    if (sysconfdir.is_absolute()) {
        return sysconfdir;
    }
    if (prefix == "/usr" || prefix == "/") {
        return fs::path("/") / sysconfdir;
    }
    if (const auto text = prefix.string(); text.starts_with("/opt/")) {
        return fs::path("/") / sysconfdir / text.substr(1);
    }
    return prefix / sysconfdir;
}

}  // namespace

std::string default_config_path_for(const std::string& program, const std::string& bindir,
                                    const std::string& sysconfdir, const std::string& forced) {
    if (!forced.empty()) {
        return (fs::path(forced) / "gportd.json").string();
    }
    const auto prefix = installed_prefix(fs::path(program), fs::path(bindir));
    if (program.empty() || !prefix) {
        return std::string(kFallbackConfigPath);
    }
    return (sysconfdir_of(*prefix, sysconfdir) / "gportd" / "gportd.json").string();
}

std::string default_config_path() {
    std::error_code error;
    const auto program = fs::read_symlink("/proc/self/exe", error);
    return default_config_path_for(error ? std::string() : program.string(), GPORT_INSTALL_BINDIR,
                                   GPORT_INSTALL_SYSCONFDIR, GPORT_CONFIG_DIR);
}

}  // namespace gport::config
