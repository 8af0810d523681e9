// JSON text to a document, with the errors a person can act on: where the
// syntax broke (line, column, byte) and which keys appear twice (the JSON
// library would silently keep only one of them).
#pragma once

#include <optional>
#include <string_view>

#include "reader.hpp"

namespace gport::config::detail {

// Comments (// and /* */) are allowed. Returns nothing after a syntax error.
std::optional<Json> parse_json(std::string_view text, Reader& reader);

}  // namespace gport::config::detail
