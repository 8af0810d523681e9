// Typed reads of JSON values that record a message for every bad value
// instead of stopping: the loader visits the whole file and reports all
// problems in one go.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "gport/config/config.hpp"
#include "gport/config/result.hpp"

namespace gport::config::detail {

// ordered_json keeps the file's key order, so messages come out in the order
// the user wrote the keys.
using Json = nlohmann::ordered_json;

// What a value is, for "expected X, got Y": scalars verbatim (cut short),
// containers by kind, so that nothing large or deep is ever printed.
std::string describe(const Json& value);

class Reader {
  public:
    explicit Reader(std::string_view origin) : origin_(origin) {}

    // "<origin>: <path>: <problem>"
    void error(std::string_view path, std::string_view problem);
    // "<origin>: <message>", for problems that belong to no single key.
    void error(std::string_view message);

    std::size_t error_count() const { return errors_.size(); }
    // Whether the value at `path` was refused (by error(path, problem)).
    bool refused(std::string_view path) const;
    Errors take_errors() { return Errors{std::move(errors_)}; }

    // Each returns nothing (after recording why) when the value has the wrong
    // type or lies outside [min, max].
    std::optional<std::int64_t> integer(const Json& value, std::string_view path, std::int64_t min,
                                        std::int64_t max);
    std::optional<double> number(const Json& value, std::string_view path, double min, double max);
    std::optional<Millis> millis(const Json& value, std::string_view path, std::int64_t min,
                                 std::int64_t max);
    // A string without NUL characters (they would silently cut C APIs short).
    std::optional<std::string> string(const Json& value, std::string_view path);
    std::optional<bool> boolean(const Json& value, std::string_view path);
    // Checks `value` is an object; `path` is empty for the whole file and
    // `allowed` lists the keys it may hold (for the message).
    bool object(const Json& value, std::string_view path,
                const std::vector<std::string_view>& allowed);
    // Records that `path` (empty at the top) holds `key`, which is not allowed.
    void unknown_key(std::string_view path, std::string_view key,
                     const std::vector<std::string_view>& allowed);

  private:
    std::string origin_;
    std::vector<std::string> errors_;
    std::set<std::string, std::less<>> refused_;
};

}  // namespace gport::config::detail
