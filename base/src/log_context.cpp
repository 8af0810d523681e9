#include "gport/base/log_context.hpp"

#include <algorithm>
#include <array>
#include <iterator>
#include <stdexcept>

namespace gport::base {

namespace {

constexpr std::size_t kMaxNameLength = 64;

// Fields the journal sink writes itself.
constexpr std::array<std::string_view, 6> kSinkFields = {
    "MESSAGE", "PRIORITY", "SYSLOG_IDENTIFIER", "CODE_FILE", "CODE_LINE", "CODE_FUNC"};

bool valid_name_char(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

auto by_name(std::string_view name) {
    return [name](const LogField& field) { return field.name == name; };
}

}  // namespace

void LogContext::validate_name(std::string_view name) {
    const std::string quoted = "journal field name '" + std::string(name) + "'";
    if (name.empty() || name.size() > kMaxNameLength) {
        throw std::invalid_argument(quoted + " must be 1 to 64 characters long");
    }
    if (!std::all_of(name.begin(), name.end(), valid_name_char)) {
        throw std::invalid_argument(quoted + " may contain only A-Z, 0-9 and '_'");
    }
    if (name.front() == '_' || (name.front() >= '0' && name.front() <= '9')) {
        throw std::invalid_argument(quoted +
                                    " must not start with '_' (reserved for journald) or a digit");
    }
    if (std::find(kSinkFields.begin(), kSinkFields.end(), name) != kSinkFields.end()) {
        throw std::invalid_argument(quoted + " is set by the journal sink itself");
    }
}

void LogContext::set(std::string_view name, std::string value) {
    validate_name(name);
    const auto it = std::find_if(persistent_.begin(), persistent_.end(), by_name(name));
    if (it != persistent_.end()) {
        it->value = std::move(value);
    } else {
        persistent_.emplace_back(name, std::move(value));
    }
}

void LogContext::erase(std::string_view name) {
    std::erase_if(persistent_, by_name(name));
}

const std::string* LogContext::find(std::string_view name) const {
    const auto it = std::find_if(persistent_.begin(), persistent_.end(), by_name(name));
    return it != persistent_.end() ? &it->value : nullptr;
}

bool LogContext::scoped_has(std::string_view name) const {
    return std::any_of(scoped_.begin(), scoped_.end(), by_name(name));
}

void LogContext::append_to(std::vector<std::string>& out) const {
    for (const auto& field : persistent_) {
        if (!scoped_has(field.name)) {
            out.push_back(field.name + "=" + field.value);
        }
    }
    // A nested LogFields overrides an outer one with the same name.
    for (auto it = scoped_.begin(); it != scoped_.end(); ++it) {
        if (std::none_of(std::next(it), scoped_.end(), by_name(it->name))) {
            out.push_back(it->name + "=" + it->value);
        }
    }
}

LogFields::LogFields(LogContext& context, std::initializer_list<LogField> fields)
    : LogFields(context, std::span<const LogField>(fields.begin(), fields.size())) {}

LogFields::LogFields(LogContext& context, std::span<const LogField> fields)
    : context_(context), base_(context.scoped_.size()) {
    for (const auto& field : fields) {
        LogContext::validate_name(field.name);
    }
    context_.scoped_.insert(context_.scoped_.end(), fields.begin(), fields.end());
}

LogFields::~LogFields() {
    auto& scoped = context_.scoped_;
    scoped.erase(scoped.begin() + static_cast<std::ptrdiff_t>(base_), scoped.end());
}

LogContext& process_log_context() {
    static LogContext context;
    return context;
}

}  // namespace gport::base
