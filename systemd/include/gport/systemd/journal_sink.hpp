// An spdlog sink that writes to journald natively, with structured fields.
//
// Each entry carries MESSAGE, PRIORITY (syslog level), SYSLOG_IDENTIFIER,
// CODE_FILE/CODE_LINE/CODE_FUNC when the call site is known (the
// SPDLOG_LOGGER_* macros), and the fields of the base::LogContext. spdlog 1.10's
// own systemd sink cannot carry custom fields, hence this one.
#pragma once

#include <spdlog/details/null_mutex.h>
#include <spdlog/sinks/base_sink.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gport/base/log_context.hpp"

namespace gport::systemd {

// Sends one journal entry, given as "FIELD=value" strings (a value may hold
// newlines). Returns 0 on success or a negative errno.
using JournalSendFn = std::function<int(const std::vector<std::string>& fields)>;

// The default JournalSendFn: sd_journal_sendv(3).
int send_to_journal(const std::vector<std::string>& fields);

// The syslog priority journald files an spdlog level under:
// trace and debug 7, info 6, warn 4, error 3, critical 2.
int journal_priority(spdlog::level::level_enum level);

// null_mutex: gportd logs from its single event-loop thread only, like the
// LogContext it reads.
class JournalSink final : public spdlog::sinks::base_sink<spdlog::details::null_mutex> {
  public:
    // `identifier` becomes SYSLOG_IDENTIFIER. `context` may be null (no
    // extra fields). When `send` fails, the entry goes to stderr as
    // "<priority>message", which journald's stream reader also understands.
    JournalSink(std::string identifier, std::shared_ptr<const base::LogContext> context,
                JournalSendFn send = send_to_journal);

  protected:
    void sink_it_(const spdlog::details::log_msg& msg) override;
    void flush_() override {}

  private:
    void build_fields(const spdlog::details::log_msg& msg);

    std::string identifier_;
    std::shared_ptr<const base::LogContext> context_;
    JournalSendFn send_;
    std::vector<std::string> fields_;  // reused between entries
};

}  // namespace gport::systemd
