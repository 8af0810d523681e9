// A strict reader of one CSV record as RFC 4180 writes it, for the tests of
// gportctl captures --csv: every field must be in double quotes (a quote in
// it doubled), fields separated by commas, nothing after the last one.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gport::testing {

// The fields of `line` (without its line break); none when a field is not
// quoted, a quote is not doubled or something follows a closing quote.
inline std::optional<std::vector<std::string>> quoted_csv_fields(std::string_view line) {
    std::vector<std::string> fields;
    std::size_t i = 0;
    for (;;) {
        if (i >= line.size() || line[i] != '"') {
            return std::nullopt;
        }
        std::string field;
        for (++i;; ++i) {
            if (i >= line.size()) {
                return std::nullopt;  // no closing quote
            }
            if (line[i] == '"') {
                if (i + 1 < line.size() && line[i + 1] == '"') {
                    field += '"';
                    ++i;
                    continue;
                }
                break;
            }
            field += line[i];
        }
        fields.push_back(std::move(field));
        ++i;  // past the closing quote
        if (i == line.size()) {
            return fields;
        }
        if (line[i] != ',') {
            return std::nullopt;
        }
        ++i;
    }
}

}  // namespace gport::testing
