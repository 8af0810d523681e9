// Start-up's side of the capture log: the directory checked, the kept files
// and the reservation read back, bounded whatever the files hold (a state
// directory's files are data, not trusted to be gportd's own).
#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "capture_mark.hpp"
#include "gport/base/json_depth.hpp"
#include "gport/capture/capture_writer.hpp"

namespace gport::capture {
namespace {

constexpr std::size_t kChunkBytes = 65536;

// Why lines of one file were skipped.
struct Skipped {
    std::uint64_t not_capture = 0;  // cut short by a crash or a full disk, or not ours
    std::uint64_t too_long = 0;
    std::uint64_t too_deep = 0;
    std::uint64_t out_of_range = 0;
    std::uint64_t repeated = 0;

    std::uint64_t total() const {
        return not_capture + too_long + too_deep + out_of_range + repeated;
    }
    std::string describe() const {
        std::vector<std::string> parts;
        const auto part = [&](std::uint64_t n, const char* what) {
            if (n > 0) {
                parts.push_back(fmt::format("{} {}", n, what));
            }
        };
        part(not_capture, "not a capture");
        part(too_long, fmt::format("longer than {} bytes", kMaxCaptureLineBytes).c_str());
        part(too_deep, fmt::format("nested deeper than {}", kMaxCaptureLineDepth).c_str());
        part(out_of_range, fmt::format("an index outside 1..{}", kMaxCaptureIndex).c_str());
        part(repeated, "an index read already");
        return fmt::format("{}", fmt::join(parts, ", "));
    }
};

// The newest `keep` lines by index, and the highest index seen.
class Newest {
  public:
    explicit Newest(std::size_t keep) : keep_(keep) {}
    // False when the index is kept already (the line is dropped).
    bool add(std::uint64_t index, const std::string& line) {
        if (lines_.contains(index)) {
            return false;
        }
        highest_ = std::max(highest_, index);
        if (lines_.size() >= keep_ && (keep_ == 0 || index < lines_.begin()->first)) {
            return true;  // older than every line kept
        }
        lines_.emplace(index, line);
        if (lines_.size() > keep_) {
            lines_.erase(lines_.begin());
        }
        return true;
    }
    std::uint64_t highest() const { return highest_; }
    std::vector<std::string> take() {
        std::vector<std::string> out;
        out.reserve(lines_.size());
        for (auto& [index, line] : lines_) {
            out.push_back(std::move(line));
        }
        return out;
    }

  private:
    std::size_t keep_;
    std::map<std::uint64_t, std::string> lines_;
    std::uint64_t highest_ = 0;
};

// The index of a capture line in 1..kMaxCaptureIndex; nullopt (counted) if not.
std::optional<std::uint64_t> capture_index(const std::string& line, Skipped& skipped) {
    if (base::nested_deeper_than(line, kMaxCaptureLineDepth)) {
        ++skipped.too_deep;  // before the parser, which recurses once per level
        return std::nullopt;
    }
    const auto capture = nlohmann::json::parse(line, nullptr, false);
    const auto index = capture.is_object() ? capture.find("index") : capture.end();
    if (!capture.is_object() || index == capture.end() || !index->is_number_unsigned()) {
        ++skipped.not_capture;
        return std::nullopt;
    }
    const auto value = index->get<std::uint64_t>();
    if (value < 1 || value > kMaxCaptureIndex) {
        ++skipped.out_of_range;
        return std::nullopt;
    }
    return value;
}

// Hands each line of what fd holds (at most `budget` bytes) to on_line;
// never holds more than kMaxCaptureLineBytes of one: a longer line is
// counted and skipped as it streams past, as is the first when
// `partial_first` (a file read from its middle). A read error's errno.
template <typename OnLine>
std::optional<int> for_each_line(int fd, std::uint64_t budget, bool partial_first, Skipped& skipped,
                                 OnLine on_line) {
    std::vector<char> buffer(kChunkBytes);
    std::string line;
    bool skipping = partial_first;
    while (budget > 0) {
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(budget, kChunkBytes));
        const auto n = ::read(fd, buffer.data(), want);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return n < 0 ? std::optional(errno) : std::nullopt;
        }
        budget -= static_cast<std::uint64_t>(n);
        std::string_view chunk(buffer.data(), static_cast<std::size_t>(n));
        for (;;) {
            const auto end = chunk.find('\n');
            const auto piece = chunk.substr(0, end);
            if (!skipping && line.size() + piece.size() > kMaxCaptureLineBytes) {
                skipping = true;
                ++skipped.too_long;
                line.clear();
            } else if (!skipping) {
                line.append(piece);
            }
            if (end == std::string_view::npos) {
                break;
            }
            if (!skipping) {
                on_line(line);
            }
            line.clear();
            skipping = false;
            chunk.remove_prefix(end + 1);
        }
    }
    if (!skipping && !line.empty()) {
        on_line(line);  // a last line without its '\n'
    }
    return std::nullopt;
}

// Opens a file of the log to read (never through a symlink); -1 when there
// is nothing to read (a problem added unless it does not exist).
int open_to_read(const std::string& path, struct stat& st, RestoredCaptures& out) {
    const int fd = open_no_follow(path, O_RDONLY);
    if (fd < 0) {
        if (errno != ENOENT) {
            out.problems.push_back(fmt::format("{}: {}", path, open_error(errno)));
        }
        return -1;
    }
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        // A device (/dev/full would read zeros forever), a FIFO, a directory.
        out.problems.push_back(fmt::format("{}: not a regular file; not read", path));
        ::close(fd);
        return -1;
    }
    return fd;
}

void read_file(const std::string& path, std::uint64_t max_bytes, Newest& newest,
               RestoredCaptures& out) {
    struct stat st {};
    const int fd = open_to_read(path, st, out);
    if (fd < 0) {
        return;
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    const bool partial = size > max_bytes;
    if (partial) {  // never written so by gportd: a lowered max_file_bytes, or not ours
        ::lseek(fd, static_cast<off_t>(size - max_bytes), SEEK_SET);
        out.problems.push_back(
            fmt::format("{}: {} bytes, more than captures.max_file_bytes; only its last {} read",
                        path, size, max_bytes));
    }
    Skipped skipped;
    const auto error = for_each_line(fd, max_bytes, partial, skipped, [&](const std::string& line) {
        if (const auto index = capture_index(line, skipped); index && !newest.add(*index, line)) {
            ++skipped.repeated;
        }
    });
    ::close(fd);
    if (error) {
        out.problems.push_back(fmt::format("{}: {}", path, std::strerror(*error)));
    }
    if (skipped.total() > 0) {
        out.problems.push_back(
            fmt::format("{}: {} line(s) skipped ({})", path, skipped.total(), skipped.describe()));
    }
}

void read_mark(const std::string& path, RestoredCaptures& out) {
    struct stat st {};
    const int fd = open_to_read(path, st, out);
    if (fd < 0) {
        return;
    }
    char record[kMarkBytes + 1];
    const auto n = ::pread(fd, record, sizeof record, 0);
    ::close(fd);
    const auto mark =
        n > 0 ? parse_mark({record, static_cast<std::size_t>(n)}) : std::optional<std::uint64_t>();
    if (!mark || *mark > kMaxCaptureIndex + 1) {
        out.problems.push_back(
            fmt::format("{}: not an index reservation ({} bytes); ignored", path, st.st_size));
        return;
    }
    out.stored_mark = mark;
}

}  // namespace

std::string CaptureFiles::file(int n) const {
    return n == 0 ? dir + "/captures.jsonl" : fmt::format("{}/captures.jsonl.{}", dir, n);
}

RestoredCaptures read_captures(const CaptureFiles& files, std::size_t keep_lines) {
    RestoredCaptures out;
    Newest newest(keep_lines);
    for (int n = files.keep_files - 1; n >= 0; --n) {
        read_file(files.file(n), files.max_file_bytes, newest, out);
    }
    read_mark(files.mark(), out);
    out.next_index = std::max(newest.highest() + 1, out.stored_mark.value_or(1));
    out.lines = newest.take();
    return out;
}

namespace {

// A symbolic link another user owns in a sticky directory anyone may write
// (/tmp, /var/tmp) is theirs to point anywhere at any time, so it is not
// followed: the rule of the kernel's fs.protected_symlinks, and of the
// capture files' own O_NOFOLLOW.
std::optional<std::string> foreign_link(const std::string& dir) {
    struct stat link {};
    if (::lstat(dir.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) {
        return std::nullopt;
    }
    const auto uid = ::geteuid();
    if (link.st_uid == uid || link.st_uid == 0) {
        return std::nullopt;
    }
    const auto slash = dir.find_last_of('/');
    const auto parent = slash == 0 ? std::string("/") : dir.substr(0, slash);
    struct stat up {};
    if (::stat(parent.c_str(), &up) != 0 || (up.st_mode & S_ISVTX) == 0 ||
        (up.st_mode & S_IWOTH) == 0) {
        return std::nullopt;
    }
    return fmt::format(
        "{} is a symbolic link of uid {} in {}, a sticky directory anyone may write: its owner "
        "can point it anywhere, so it is not followed; give the directory itself",
        dir, link.st_uid, parent);
}

}  // namespace

std::optional<std::string> check_capture_dir(const std::string& dir) {
    if (auto refused = foreign_link(dir)) {
        return refused;
    }
    if (::mkdir(dir.c_str(), 0750) != 0 && errno != EEXIST) {
        return fmt::format("{} cannot be created: {}", dir, std::strerror(errno));
    }
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0) {
        return fmt::format("{}: {}", dir, std::strerror(errno));
    }
    if (!S_ISDIR(st.st_mode)) {
        return fmt::format("{} is not a directory", dir);
    }
    const auto uid = ::geteuid();
    if (st.st_uid != uid && st.st_uid != 0) {
        return fmt::format("{} belongs to uid {}, neither gportd's ({}) nor root: chown {} {}", dir,
                           st.st_uid, uid, uid, dir);
    }
    if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) {
        return fmt::format("{} may be written by {} (mode {:04o}): chmod go-w {}", dir,
                           (st.st_mode & S_IWOTH) != 0 ? "anyone" : "its group", st.st_mode & 07777,
                           dir);
    }
    return std::nullopt;
}

}  // namespace gport::capture
