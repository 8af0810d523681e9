// Structured journal fields attached to gportd's log entries.
//
// The journal sink (systemd/include/gport/systemd/journal_sink.hpp) sends,
// with each entry, the fields of the LogContext it was given:
//   - persistent fields, set by the app when they change and sent with every
//     entry from then on: GPORT_DEVICE=/dev/gimbal, GPORT_LINK=up;
//   - scoped fields, for the duration of a LogFields object on the stack:
//     GPORT_CLIENT_PID=1234, GPORT_CLIENT_UID=1000 and GPORT_CLIENT_ID=7
//     while a client's request is handled (ipc's Dispatcher), while its
//     settings reply is delivered, and on the core's lines about its motion
//     (daemon::ClientLogScope, gport/daemon/client_log.hpp).
// A scoped field overrides a persistent one of the same name. Then, e.g.,
//     journalctl -u gportd GPORT_LINK=down
// finds what was logged while the link was down.
//
// These types need nothing but the standard library, so they live at the
// bottom of the layering (base/): the core and ipc set fields, systemd/
// sends them, and app/ hands gportd's logger process_log_context().
//
// A LogContext and its LogFields belong to the event-loop thread (gportd is
// single-threaded); they are not synchronised.
#pragma once

#include <concepts>
#include <cstddef>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gport::base {

// The fields gportd's parts agree on.
inline constexpr std::string_view kFieldDevice = "GPORT_DEVICE";         // serial device path
inline constexpr std::string_view kFieldLink = "GPORT_LINK";             // up, stale, down
inline constexpr std::string_view kFieldClientPid = "GPORT_CLIENT_PID";  // SO_PEERCRED pid
inline constexpr std::string_view kFieldClientUid = "GPORT_CLIENT_UID";  // SO_PEERCRED uid
inline constexpr std::string_view kFieldClientId = "GPORT_CLIENT_ID";    // connection id

struct LogField {
    LogField(std::string_view field_name, std::string field_value)
        : name(field_name), value(std::move(field_value)) {}
    template <std::integral T>
    LogField(std::string_view field_name, T field_value)
        : name(field_name), value(std::to_string(field_value)) {}

    std::string name;
    std::string value;
};

class LogContext {
  public:
    // Sets (or replaces) a persistent field. Throws std::invalid_argument
    // when the name is not a valid journal field name (see validate_name).
    void set(std::string_view name, std::string value);

    // Removes a persistent field; absent names are ignored.
    void erase(std::string_view name);

    // The persistent field's value, or nullptr.
    [[nodiscard]] const std::string* find(std::string_view name) const;

    // Appends every current field as "NAME=value" to `out`: persistent fields
    // not overridden by a scoped one, then scoped fields, innermost last.
    void append_to(std::vector<std::string>& out) const;

    // Throws std::invalid_argument unless `name` is a field name journald
    // accepts from a client and the sink does not set itself: 1 to 64
    // characters A-Z, 0-9 and '_', not starting with '_' or a digit, and none
    // of MESSAGE, PRIORITY, SYSLOG_IDENTIFIER, CODE_FILE, CODE_LINE, CODE_FUNC.
    static void validate_name(std::string_view name);

  private:
    friend class LogFields;

    [[nodiscard]] bool scoped_has(std::string_view name) const;

    std::vector<LogField> persistent_;
    std::vector<LogField> scoped_;
};

// Adds fields to a LogContext for its own lifetime (RAII), e.g.
//     LogFields fields(context, {{kFieldClientPid, peer.pid}});
//     logger->info("client disconnected while moving: stopping");
class LogFields {
  public:
    // Throws std::invalid_argument for an invalid name (nothing is added).
    LogFields(LogContext& context, std::initializer_list<LogField> fields);
    LogFields(LogContext& context, std::span<const LogField> fields);
    ~LogFields();

    LogFields(const LogFields&) = delete;
    LogFields& operator=(const LogFields&) = delete;

  private:
    LogContext& context_;
    std::size_t base_;
};

// The process's one LogContext, the one gportd's logger reads (app/ passes
// it to systemd::make_logger). Parts below systemd/ add their scoped fields
// here. Without a journal logger (tests, stderr) the fields go nowhere.
LogContext& process_log_context();

}  // namespace gport::base
