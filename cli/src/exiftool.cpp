#include "exiftool.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

extern char** environ;

namespace gport::cli {
namespace {

using nlohmann::json;

constexpr const char* kInstall =
    "gportctl geotag needs exiftool: sudo apt install libimage-exiftool-perl";
// exiftool's output is read whole: a folder of 100,000 images is well below.
constexpr std::size_t kMaxOutput = 64U << 20U;

struct Ran {
    int status = -1;  // exit status, or -1 when it did not run
    std::string out;  // stdout and stderr, joined
};

// Runs exiftool with `args` (stdin closed), capturing its output.
Result<Ran, ExifError> run_exiftool(const std::vector<std::string>& args) {
    std::array<int, 2> pipe_fds{};
    if (::pipe2(pipe_fds.data(), O_CLOEXEC) != 0) {
        return gport::unexpected(
            ExifError{fmt::format("cannot run exiftool: pipe: {}", std::strerror(errno))});
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
    std::vector<std::string> argv_text{"exiftool"};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_text) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = ::posix_spawnp(&pid, "exiftool", &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[1]);
    if (spawned != 0) {
        ::close(pipe_fds[0]);
        return gport::unexpected(ExifError{
            spawned == ENOENT ? std::string(kInstall)
                              : fmt::format("cannot run exiftool: {}", std::strerror(spawned))});
    }
    Ran ran;
    std::array<char, 65536> buffer{};
    for (;;) {
        const auto n = ::read(pipe_fds[0], buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            break;
        }
        if (ran.out.size() < kMaxOutput) {
            ran.out.append(buffer.data(), static_cast<std::size_t>(n));
        }
    }
    ::close(pipe_fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    ran.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (ran.status == 127) {  // posix_spawnp found no exiftool (the child's exec failed)
        return gport::unexpected(ExifError{std::string(kInstall)});
    }
    return ran;
}

// An argument file, one argument a line: file names may hold spaces but
// not newlines (refused before).
Result<std::string, ExifError> write_argfile(const std::vector<std::string>& lines) {
    char path[] = "/tmp/gportctl-geotag-XXXXXX";
    const int fd = ::mkstemp(path);
    if (fd < 0) {
        return gport::unexpected(ExifError{
            fmt::format("cannot write exiftool's argument file: {}", std::strerror(errno))});
    }
    ::close(fd);
    std::ofstream file(path, std::ios::trunc);
    for (const auto& line : lines) {
        file << line << '\n';
    }
    if (!file.flush()) {
        std::remove(path);
        return gport::unexpected(ExifError{std::string("cannot write exiftool's argument file")});
    }
    return std::string(path);
}

}  // namespace

Result<json, ExifError> read_image_times(const std::string& dir) {
    auto ran =
        run_exiftool({"-json", "-n", "-q", "-q", "-ext", "jpg", "-ext", "jpeg", "-DateTimeOriginal",
                      "-SubSecTimeOriginal", "-OffsetTimeOriginal", dir});
    if (!ran) {
        return gport::unexpected(ran.error());
    }
    if (ran->out.find_first_not_of(" \t\r\n") == std::string::npos) {
        return json::array();  // no JPEG in it: exiftool prints nothing
    }
    auto parsed = json::parse(ran->out, nullptr, false);
    if (!parsed.is_array()) {
        return gport::unexpected(ExifError{fmt::format("exiftool could not read {} (exit {}): {}",
                                                       dir, ran->status, ran->out.substr(0, 500))});
    }
    return parsed;
}

std::optional<ExifError> write_image_tags(const std::vector<std::string>& files,
                                          const std::vector<std::vector<std::string>>& tags) {
    std::vector<std::string> lines;
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (files[i].find('\n') != std::string::npos) {
            return ExifError{fmt::format("a file name holds a newline: {}", files[i])};
        }
        if (i > 0) {
            lines.emplace_back("-execute");
        }
        lines.insert(lines.end(), tags[i].begin(), tags[i].end());
        lines.push_back(files[i]);
    }
    auto argfile = write_argfile(lines);
    if (!argfile) {
        return argfile.error();
    }
    auto ran = run_exiftool({"-q", "-m", "-@", *argfile});
    std::remove(argfile->c_str());
    if (!ran) {
        return ran.error();
    }
    if (ran->status != 0) {
        return ExifError{
            fmt::format("exiftool failed (exit {}): {}", ran->status, ran->out.substr(0, 2000))};
    }
    return std::nullopt;
}

}  // namespace gport::cli
