#include "gport/cli/printable.hpp"

#include <fmt/format.h>

#include "gport/client/printable.hpp"

namespace gport::cli {

std::string printable(std::string_view text) {
    return client::printable(text);
}

std::string json_line(const nlohmann::json& value) {
    const auto dumped = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    std::string out;
    out.reserve(dumped.size());
    for (std::size_t i = 0; i < dumped.size(); ++i) {
        const auto c = static_cast<unsigned char>(dumped[i]);
        const auto next = i + 1 < dumped.size() ? static_cast<unsigned char>(dumped[i + 1]) : 0;
        if (c == 0x7F) {
            out += "\\u007f";
        } else if (c == 0xC2 && next >= 0x80 && next <= 0x9F) {
            // Valid UTF-8 after the dump: 0xC2 is always a lead byte here.
            out += fmt::format("\\u{:04x}", next);
            ++i;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out;
}

}  // namespace gport::cli
