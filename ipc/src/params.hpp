// Validation of a method's "params" object. Every refusal throws
// InvalidParams with a message that names the field and what is allowed; the
// dispatcher turns it into -32602. Handlers stay short and read top-down.
// The throw is the one kept on purpose for bad input (docs/architecture.md,
// "Errors"): it never leaves the dispatcher's run_method.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "gport/daemon/api.hpp"

namespace gport::ipc::detail {

struct InvalidParams : std::runtime_error {
    using std::runtime_error::runtime_error;
};

class Params {
  public:
    // `params` may be absent (null), an object, or an empty array.
    explicit Params(const nlohmann::json& params);

    // Refuses any member not in `allowed`, naming the allowed ones.
    const Params& only(std::initializer_list<std::string_view> allowed) const;

    std::optional<double> number(std::string_view name) const;
    // Degrees (or °/s) to 0.01 units; absent means 0.
    std::int16_t centi(std::string_view name) const;
    protocol::Axes axes() const;  // "roll", "pitch", "yaw"
    // `bound`, when given, names where `max` comes from (a config key).
    std::optional<std::int64_t> integer(std::string_view name, std::int64_t min, std::int64_t max,
                                        std::string_view bound = {}) const;
    std::optional<bool> boolean(std::string_view name) const;
    // A non-empty array of distinct names, each one of `allowed`.
    std::optional<std::vector<std::string>> names(std::string_view name,
                                                  std::span<const std::string_view> allowed) const;

  private:
    const nlohmann::json* find(std::string_view name) const;

    const nlohmann::json& params_;
};

// "a, b and c" for messages.
std::string join(std::span<const std::string_view> names);

}  // namespace gport::ipc::detail
