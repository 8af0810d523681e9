// The capture log's reservation file, DIR/captures.next (docs/operations.md,
// "The capture log"): the index high-water mark, below which indexes may
// have been given. One fixed-size record, rewritten in place:
//
//   offset  size  content
//   0       20    the mark, decimal, zero-padded ("00000000000000001058")
//   20      1     '\n'
//
// Rewritten with one pwrite at offset 0 and fdatasync: the same 21 bytes of
// the same block, so a full disk still takes it (on a filesystem that
// overwrites in place: ext4, f2fs, tmpfs; not a copy-on-write one). A record
// within one sector is written whole or not at all by the devices we run on.
// Every file of the log is opened with O_NOFOLLOW: a planted symlink is
// refused, never followed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace gport::capture {

inline constexpr std::size_t kMarkBytes = 21;

// The record for `mark`.
std::string format_mark(std::uint64_t mark);
// The mark in a record, or nullopt when `text` is not exactly one.
std::optional<std::uint64_t> parse_mark(std::string_view text);

// open(2) with O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK (a FIFO's open does not
// wait for a reader) added; -1 and errno as open.
int open_no_follow(const std::string& path, int flags, unsigned mode = 0640);
// strerror, with ELOOP named for what it means here.
std::string open_error(int error);

// Opens (creating) the mark file for writing; -1 with errno when it cannot
// be, or is not a regular file (errno EINVAL).
int open_mark(const std::string& path);
// Writes `mark` durably; an error text, or nullopt when it is on the disk.
std::optional<std::string> write_mark(int fd, std::uint64_t mark);

}  // namespace gport::capture
