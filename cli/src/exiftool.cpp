#include "exiftool.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

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

// An argument file, one argument a line. A path may hold spaces, but not a
// line break anywhere (a folder above the image's too): exiftool would read
// the text after it as options of its own (-if runs Perl), and it drops a
// carriage return at a line's end.
Result<std::string, ExifError> write_argfile(const std::vector<std::string>& lines) {
    for (const auto& line : lines) {
        if (line.find_first_of("\r\n") != std::string::npos) {
            return gport::unexpected(ExifError{fmt::format(
                "a path holds a line break, which exiftool's argument file cannot carry: {}",
                line)});
        }
    }
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

// A name that ends in .jpg or .jpeg (any case), blanks after it allowed.
bool is_jpeg_name(std::string name) {
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) {
        name.pop_back();
    }
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return name.ends_with(".jpg") || name.ends_with(".jpeg");
}

// The JPEG files in `dir`, sorted.
Result<std::vector<std::string>, ExifError> jpeg_files(const std::string& dir) {
    std::vector<std::string> files;
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const auto name = it->path().filename().string();
        if (!is_jpeg_name(name) || !it->is_regular_file(ec)) {
            continue;
        }
        files.push_back(it->path().string());
    }
    if (ec) {
        return gport::unexpected(ExifError{fmt::format("cannot read {}: {}", dir, ec.message())});
    }
    std::sort(files.begin(), files.end());
    return files;
}

// Pix4D's XMP namespace, for the position's accuracy (XMP-Camera:GPSXYAccuracy
// and GPSZAccuracy, 1-sigma metres: what Pix4D and OpenDroneMap read), which
// exiftool 12.57 (Debian 12) does not define: an exiftool configuration
// file defines it for the writes. Reading needs none (exiftool reads any XMP).
const std::vector<std::string> kPix4dConfig{
    "%Image::ExifTool::UserDefined = (",
    "    'Image::ExifTool::XMP::Main' => {",
    "        Camera => { SubDirectory => { TagTable => 'Image::ExifTool::UserDefined::Camera' } },",
    "    },",
    ");",
    "%Image::ExifTool::UserDefined::Camera = (",
    "    GROUPS => { 0 => 'XMP', 1 => 'XMP-Camera', 2 => 'Location' },",
    "    NAMESPACE => { 'Camera' => 'http://pix4d.com/camera/1.0/' },",
    "    WRITABLE => 'real',",
    "    GPSXYAccuracy => { },",
    "    GPSZAccuracy => { },",
    ");",
    "1;",
};

// Runs exiftool with `lines` as its argument file, then `args`; with
// `config`, under that configuration (-config must come first).
Result<Ran, ExifError> run_with_argfile(const std::vector<std::string>& lines,
                                        std::vector<std::string> args,
                                        const std::vector<std::string>* config = nullptr) {
    auto argfile = write_argfile(lines);
    if (!argfile) {
        return gport::unexpected(argfile.error());
    }
    args.insert(args.begin(), {"-@", *argfile});
    std::optional<std::string> config_file;
    if (config != nullptr) {
        auto written = write_argfile(*config);
        if (!written) {
            std::remove(argfile->c_str());
            return gport::unexpected(written.error());
        }
        config_file = *written;
        args.insert(args.begin(), {"-config", *config_file});
    }
    auto ran = run_exiftool(args);
    std::remove(argfile->c_str());
    if (config_file) {
        std::remove(config_file->c_str());
    }
    return ran;
}

// After file i's command, exiftool prints this line (-echo4: to stderr, in
// order with its messages about the file).
std::string marker(std::size_t i) {
    return fmt::format("{{gportctl geotag: done {}}}", i);
}

// exiftool's "Error: MESSAGE - FILE" lines for each file, told apart by
// the markers; empty when none.
std::vector<std::optional<std::string>> errors_by_file(const std::string& out, std::size_t files) {
    std::vector<std::optional<std::string>> errors(files);
    std::size_t file = 0;
    std::istringstream lines(out);
    for (std::string line; std::getline(lines, line) && file < files;) {
        if (line == marker(file)) {
            ++file;
        } else if (line.starts_with("Error: ")) {
            auto message = line.substr(7);
            if (const auto dash = message.rfind(" - "); dash != std::string::npos) {
                message.resize(dash);  // " - FILE": the caller names it
            }
            errors[file] = errors[file] ? *errors[file] + "; " + message : message;
        }
    }
    for (; file < files; ++file) {
        errors[file] = errors[file].value_or("exiftool stopped before it");
    }
    return errors;
}

}  // namespace

Result<json, ExifError> read_image_times(const std::string& dir) {
    auto files = jpeg_files(dir);
    if (!files) {
        return gport::unexpected(files.error());
    }
    if (files->empty()) {
        return json::array();
    }
    auto ran = run_with_argfile(*files, {"-json", "-n", "-q", "-q", "-DateTimeOriginal",
                                         "-SubSecTimeOriginal", "-OffsetTimeOriginal"});
    if (!ran) {
        return gport::unexpected(ran.error());
    }
    auto parsed = json::parse(ran->out, nullptr, false);
    if (!parsed.is_array()) {
        return gport::unexpected(ExifError{fmt::format("exiftool could not read {} (exit {}): {}",
                                                       dir, ran->status, ran->out.substr(0, 500))});
    }
    return parsed;
}

Result<std::vector<std::optional<std::string>>, ExifError> write_image_tags(
    const std::vector<std::string>& files, const std::vector<std::vector<std::string>>& tags) {
    std::vector<std::string> lines;
    for (std::size_t i = 0; i < files.size(); ++i) {
        if (i > 0) {
            lines.emplace_back("-execute");
        }
        lines.insert(lines.end(), tags[i].begin(), tags[i].end());
        lines.insert(lines.end(), {files[i], "-echo4", marker(i)});
    }
    // -common_args: -q and -m for every file's command, not just the first.
    auto ran = run_with_argfile(lines, {"-common_args", "-q", "-q", "-m"}, &kPix4dConfig);
    if (!ran) {
        return gport::unexpected(ran.error());
    }
    auto errors = errors_by_file(ran->out, files.size());
    if (ran->status != 0 &&
        std::none_of(errors.begin(), errors.end(), [](const auto& e) { return e.has_value(); })) {
        return gport::unexpected(ExifError{
            fmt::format("exiftool failed (exit {}): {}", ran->status, ran->out.substr(0, 2000))});
    }
    return errors;
}

}  // namespace gport::cli
