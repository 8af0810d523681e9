#include "gport/systemd/logger.hpp"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <sys/stat.h>
#include <unistd.h>

#include <charconv>
#include <cstdlib>

#include "gport/systemd/journal_sink.hpp"

namespace gport::systemd {

namespace {

// One decimal unsigned number filling `text` exactly.
template <typename T>
bool parse_decimal(std::string_view text, T& value) {
    if (text.empty()) {
        return false;
    }
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    return error == std::errc() && end == text.data() + text.size();
}

}  // namespace

bool is_journal_stream(int fd, std::string_view journal_stream) {
    const auto colon = journal_stream.find(':');
    if (colon == std::string_view::npos) {
        return false;
    }
    unsigned long long device = 0;
    unsigned long long inode = 0;
    if (!parse_decimal(journal_stream.substr(0, colon), device) ||
        !parse_decimal(journal_stream.substr(colon + 1), inode)) {
        return false;
    }
    struct stat st {};
    if (fstat(fd, &st) != 0) {
        return false;
    }
    return static_cast<unsigned long long>(st.st_dev) == device &&
           static_cast<unsigned long long>(st.st_ino) == inode;
}

bool stderr_is_journal() {
    const char* value = std::getenv("JOURNAL_STREAM");
    return value != nullptr && is_journal_stream(STDERR_FILENO, value);
}

LogTarget resolve_target(LogTarget target) {
    if (target != LogTarget::automatic) {
        return target;
    }
    return stderr_is_journal() ? LogTarget::journal : LogTarget::stderr_stream;
}

std::shared_ptr<spdlog::logger> make_logger(const LoggerOptions& options,
                                            std::shared_ptr<const base::LogContext> context) {
    spdlog::sink_ptr sink;
    if (resolve_target(options.target) == LogTarget::journal) {
        sink = std::make_shared<JournalSink>(options.name, std::move(context));
    } else {
        sink = std::make_shared<spdlog::sinks::stderr_sink_st>();
        sink->set_formatter(std::make_unique<spdlog::pattern_formatter>(
            std::string(kStderrPattern), spdlog::pattern_time_type::local, std::string("\n")));
    }
    auto logger = std::make_shared<spdlog::logger>(options.name, std::move(sink));
    logger->set_level(options.level);
    // Warnings and worse reach the journal or the terminal at once.
    logger->flush_on(spdlog::level::warn);
    return logger;
}

}  // namespace gport::systemd
