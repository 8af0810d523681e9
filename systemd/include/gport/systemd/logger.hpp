// gportd's logger: native journald when stderr is the journal, else stderr.
#pragma once

#include <spdlog/common.h>
#include <spdlog/logger.h>

#include <memory>
#include <string>
#include <string_view>

#include "gport/base/log_context.hpp"

namespace gport::systemd {

// True when `fd` is the stream described by `journal_stream`, the value of
// JOURNAL_STREAM ("<device>:<inode>", decimal) that systemd sets for a
// service whose output goes to the journal. False for an empty or malformed
// value, or when fstat(fd) fails.
bool is_journal_stream(int fd, std::string_view journal_stream);

// is_journal_stream(STDERR_FILENO, $JOURNAL_STREAM): stderr still is the
// journal (it is not when the daemon was started from a shell inside a unit
// and its stderr redirected, for example).
bool stderr_is_journal();

enum class LogTarget {
    automatic,  // journal when stderr_is_journal(), else stderr
    journal,
    stderr_stream,
};

// The stderr format: no colours (the output often goes to files and pipes),
// local time to the millisecond, then the level: "2025-03-01 12:00:00.123
// [warning] link stale".
inline constexpr std::string_view kStderrPattern = "%Y-%m-%d %H:%M:%S.%e [%l] %v";

struct LoggerOptions {
    std::string name = "gportd";  // the logger's name and SYSLOG_IDENTIFIER
    spdlog::level::level_enum level = spdlog::level::info;
    LogTarget target = LogTarget::automatic;
};

// The target `automatic` stands for now.
LogTarget resolve_target(LogTarget target);

// A logger writing to the resolved target. Journal entries carry the
// fields of `context` (may be null). Not registered with spdlog; call
// spdlog::set_default_logger() to make it the default.
std::shared_ptr<spdlog::logger> make_logger(const LoggerOptions& options,
                                            std::shared_ptr<const base::LogContext> context);

}  // namespace gport::systemd
