#include "reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "checks.hpp"

namespace gport::config::detail {
namespace {

std::string join(const std::vector<std::string_view>& words) {
    return fmt::format("{}", fmt::join(words, ", "));
}

std::string qualified(std::string_view path, std::string_view key) {
    return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

}  // namespace

std::string describe(const Json& value) {
    switch (value.type()) {
        case Json::value_t::object:
            return "an object";
        case Json::value_t::array:
            return "an array";
        case Json::value_t::string:
            return json_quoted(value.get_ref<const std::string&>());
        case Json::value_t::null:
            return "null";
        default:  // numbers and booleans are short
            return value.dump();
    }
}

void Reader::error(std::string_view path, std::string_view problem) {
    refused_.emplace(path);
    errors_.push_back(fmt::format("{}: {}: {}", origin_, path, problem));
}

bool Reader::refused(std::string_view path) const {
    return refused_.contains(path);
}

void Reader::error(std::string_view message) {
    errors_.push_back(fmt::format("{}: {}", origin_, message));
}

std::optional<std::int64_t> Reader::integer(const Json& value, std::string_view path,
                                            std::int64_t min, std::int64_t max) {
    const auto problem = [&] {
        error(path,
              fmt::format("must be an integer from {} to {}, got {}", min, max, describe(value)));
        return std::nullopt;
    };
    if (value.is_number_unsigned()) {
        // Checked as unsigned first: values above INT64_MAX must not wrap.
        const auto n = value.get<std::uint64_t>();
        if (n > static_cast<std::uint64_t>(max) || static_cast<std::int64_t>(n) < min) {
            return problem();
        }
        return static_cast<std::int64_t>(n);
    }
    if (value.is_number_integer()) {
        const auto n = value.get<std::int64_t>();
        if (n < min || n > max) {
            return problem();
        }
        return n;
    }
    return problem();
}

std::optional<double> Reader::number(const Json& value, std::string_view path, double min,
                                     double max) {
    if (value.is_number()) {
        const auto n = value.get<double>();
        if (std::isfinite(n) && n >= min && n <= max) {
            return n;
        }
    }
    error(path, fmt::format("must be a number from {} to {}, got {}", min, max, describe(value)));
    return std::nullopt;
}

std::optional<Millis> Reader::millis(const Json& value, std::string_view path, std::int64_t min,
                                     std::int64_t max) {
    if (auto n = integer(value, path, min, max)) {
        return Millis{*n};
    }
    return std::nullopt;
}

std::optional<bool> Reader::boolean(const Json& value, std::string_view path) {
    if (!value.is_boolean()) {
        error(path, fmt::format("must be true or false, got {}", describe(value)));
        return std::nullopt;
    }
    return value.get<bool>();
}

std::optional<std::string> Reader::string(const Json& value, std::string_view path) {
    if (!value.is_string()) {
        error(path, fmt::format("must be a string, got {}", describe(value)));
        return std::nullopt;
    }
    const auto& text = value.get_ref<const std::string&>();
    if (text.find('\0') != std::string::npos) {
        error(path, fmt::format("must not contain a NUL character, got {}", json_quoted(text)));
        return std::nullopt;
    }
    return text;
}

bool Reader::object(const Json& value, std::string_view path,
                    const std::vector<std::string_view>& allowed) {
    if (!value.is_object()) {
        if (path.empty()) {
            error(fmt::format("the file must hold one JSON object with the sections {}, got {}",
                              join(allowed), describe(value)));
        } else {
            error(path, fmt::format("must be an object with the keys {}, got {}", join(allowed),
                                    describe(value)));
        }
        return false;
    }
    return true;
}

void Reader::unknown_key(std::string_view path, std::string_view key,
                         const std::vector<std::string_view>& allowed) {
    const auto where =
        path.empty() ? std::string("allowed keys") : fmt::format("allowed keys in {}", path);
    error(fmt::format("unknown key {}; {}: {}", json_quoted(qualified(path, key)), where,
                      join(allowed)));
}

}  // namespace gport::config::detail
