#include "params.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace gport::ipc::detail {
namespace {

using nlohmann::json;

const json& checked(const json& params) {
    if (params.is_null() || params.is_object() || (params.is_array() && params.empty())) {
        return params;
    }
    throw InvalidParams("params must be an object of named parameters");
}

// Member names and values are echoed in messages; a hostile one must not make
// a reply huge.
std::string truncated(std::string text) {
    constexpr std::size_t kShown = 64;
    if (text.size() > kShown) {
        text.resize(kShown);
        text += "...";
    }
    return text;
}

std::string dumped(const json& value) {
    return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string shown(std::string_view name) {
    return truncated(dumped(json(std::string(name))));
}

}  // namespace

std::string join(std::span<const std::string_view> names) {
    std::string out;
    std::size_t i = 0;
    for (auto name : names) {
        if (i > 0) {
            out += (i + 1 == names.size()) ? " and " : ", ";
        }
        out += name;
        ++i;
    }
    return out;
}

Params::Params(const json& params) : params_(checked(params)) {}

const json* Params::find(std::string_view name) const {
    if (!params_.is_object()) {
        return nullptr;
    }
    auto it = params_.find(name);
    return it == params_.end() ? nullptr : &*it;
}

const Params& Params::only(std::initializer_list<std::string_view> allowed) const {
    if (!params_.is_object()) {
        return *this;
    }
    for (const auto& [key, value] : params_.items()) {
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) {
            continue;
        }
        if (allowed.size() == 0) {
            throw InvalidParams(
                fmt::format("unknown parameter {}; this method takes no parameters", shown(key)));
        }
        throw InvalidParams(
            fmt::format("unknown parameter {}; allowed: {}", shown(key), join(allowed)));
    }
    return *this;
}

std::optional<double> Params::number(std::string_view name) const {
    const json* value = find(name);
    if (value == nullptr) {
        return std::nullopt;
    }
    if (!value->is_number()) {
        throw InvalidParams(fmt::format("{} must be a number, got {}", name, value->type_name()));
    }
    return value->get<double>();
}

std::int16_t Params::centi(std::string_view name) const {
    auto degrees = number(name);
    if (!degrees) {
        return 0;
    }
    auto centi = protocol::to_centi(*degrees, name);
    if (!centi) {
        throw InvalidParams(centi.error().message);
    }
    return *centi;
}

protocol::Axes Params::axes() const {
    return {centi("roll"), centi("pitch"), centi("yaw")};
}

std::optional<std::int64_t> Params::integer(std::string_view name, std::int64_t min,
                                            std::int64_t max, std::string_view bound) const {
    const json* value = find(name);
    if (value == nullptr) {
        return std::nullopt;
    }
    const auto refuse = [&] {
        return InvalidParams(fmt::format("{} must be an integer from {} to {}{}{}{}", name, min,
                                         max, bound.empty() ? "" : " (", bound,
                                         bound.empty() ? "" : ")"));
    };
    if (!value->is_number()) {
        throw refuse();
    }
    std::int64_t i = 0;
    if (value->is_number_float()) {
        // A whole number inside int64's range, then checked as any integer:
        // 2^63 is outside although it equals double(INT64_MAX), and casting
        // it would be undefined.
        constexpr double kTwoTo63 = 9223372036854775808.0;
        const double d = value->get<double>();
        if (!std::isfinite(d) || std::floor(d) != d || d < -kTwoTo63 || d >= kTwoTo63) {
            throw refuse();
        }
        i = static_cast<std::int64_t>(d);
    } else if (value->is_number_unsigned() &&
               value->get<std::uint64_t>() > static_cast<std::uint64_t>(max)) {
        throw refuse();
    } else {
        i = value->get<std::int64_t>();
    }
    if (i < min || i > max) {
        throw refuse();
    }
    return i;
}

std::optional<bool> Params::boolean(std::string_view name) const {
    const json* value = find(name);
    if (value == nullptr) {
        return std::nullopt;
    }
    if (!value->is_boolean()) {
        throw InvalidParams(
            fmt::format("{} must be true or false, got {}", name, value->type_name()));
    }
    return value->get<bool>();
}

std::optional<std::vector<std::string>> Params::names(
    std::string_view name, std::span<const std::string_view> allowed) const {
    const json* value = find(name);
    if (value == nullptr) {
        return std::nullopt;
    }
    const auto refuse = [&](std::string_view why) {
        return InvalidParams(
            fmt::format("{} must be a non-empty array of {}{}", name, join(allowed), why));
    };
    if (!value->is_array() || value->empty()) {
        throw refuse("");
    }
    std::vector<std::string> out;
    for (const auto& item : *value) {
        if (!item.is_string() ||
            std::find(allowed.begin(), allowed.end(), item.get<std::string>()) == allowed.end()) {
            throw refuse(fmt::format("; got {}", truncated(dumped(item))));
        }
        if (std::find(out.begin(), out.end(), item.get<std::string>()) == out.end()) {
            out.push_back(item.get<std::string>());
        }
    }
    return out;
}

}  // namespace gport::ipc::detail
