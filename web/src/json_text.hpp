// JSON as the text gport-web sends: compact, and invalid UTF-8 from gportd
// replaced rather than thrown (a page must never see half a message).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace gport::web {

inline std::string json_text(const nlohmann::json& value) {
    return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace gport::web
