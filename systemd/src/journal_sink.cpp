#include "gport/systemd/journal_sink.hpp"

#include <sys/uio.h>
#include <syslog.h>
#include <systemd/sd-journal.h>

#include <cstdio>
#include <string_view>

namespace gport::systemd {

int send_to_journal(const std::vector<std::string>& fields) {
    std::vector<iovec> iov;
    iov.reserve(fields.size());
    for (const auto& field : fields) {
        // sd_journal_sendv only reads through iov_base.
        iov.push_back({const_cast<char*>(field.data()), field.size()});
    }
    return sd_journal_sendv(iov.data(), static_cast<int>(iov.size()));
}

int journal_priority(spdlog::level::level_enum level) {
    switch (level) {
        case spdlog::level::trace:
        case spdlog::level::debug:
            return LOG_DEBUG;
        case spdlog::level::info:
            return LOG_INFO;
        case spdlog::level::warn:
            return LOG_WARNING;
        case spdlog::level::err:
            return LOG_ERR;
        case spdlog::level::critical:
            return LOG_CRIT;
        default:
            return LOG_INFO;
    }
}

JournalSink::JournalSink(std::string identifier, std::shared_ptr<const base::LogContext> context,
                         JournalSendFn send)
    : identifier_(std::move(identifier)), context_(std::move(context)), send_(std::move(send)) {}

void JournalSink::build_fields(const spdlog::details::log_msg& msg) {
    fields_.clear();
    const std::string_view payload(msg.payload.data(), msg.payload.size());
    fields_.push_back("MESSAGE=" + std::string(payload));
    fields_.push_back("PRIORITY=" + std::to_string(journal_priority(msg.level)));
    fields_.push_back("SYSLOG_IDENTIFIER=" + identifier_);
    if (!msg.source.empty()) {
        fields_.push_back(std::string("CODE_FILE=") + msg.source.filename);
        fields_.push_back("CODE_LINE=" + std::to_string(msg.source.line));
        if (msg.source.funcname != nullptr) {
            fields_.push_back(std::string("CODE_FUNC=") + msg.source.funcname);
        }
    }
    if (context_) {
        context_->append_to(fields_);
    }
}

void JournalSink::sink_it_(const spdlog::details::log_msg& msg) {
    build_fields(msg);
    if (send_(fields_) >= 0) {
        return;
    }
    // The journal socket is gone (journald restarting, or a sandbox without
    // it): keep the line, in the "<priority>" form journald's stream reader
    // parses, rather than lose it.
    std::fprintf(stderr, "<%d>%.*s\n", journal_priority(msg.level),
                 static_cast<int>(msg.payload.size()), msg.payload.data());
    std::fflush(stderr);
}

}  // namespace gport::systemd
