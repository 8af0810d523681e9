#include "title.hpp"

#include <fmt/format.h>

#include <vector>

#include "screen.hpp"
#include "text.hpp"

namespace gport::cli::monitor {
namespace {

// "…/gportd-gimbal1.sock" for "/run/gport/gportd-gimbal1.sock"; the path as
// it is when it names no directory.
std::string elided_directory(const std::string& path, const std::string& ellipsis) {
    const auto slash = path.find_last_of('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == path.size()) {
        return path;
    }
    return ellipsis + path.substr(slash);
}

// The first `cols` columns of `text`, the last one an ellipsis when cut.
std::string cut_end(const std::string& text, int cols, const std::string& ellipsis) {
    if (columns(text) <= cols) {
        return text;
    }
    const int keep = std::max(cols - columns(ellipsis), 0);
    std::string out;
    for (const auto& glyph : split_glyphs(text)) {
        if (columns(out) >= keep) {
            break;
        }
        out += glyph;
    }
    return out + ellipsis;
}

bool fits(const std::string& left, const std::string& right, int width) {
    return columns(left) + 1 + columns(right) <= width;
}

}  // namespace

Title title_for(const MonitorModel& model, int width, bool ascii) {
    const std::string ellipsis = ascii ? "..." : "…";
    const std::string program = " gportctl monitor";
    const std::string version =
        model.daemon_version.empty() ? "" : " · gportd " + model.daemon_version;
    const std::string short_socket = elided_directory(model.socket, ellipsis);
    const std::vector<std::string> lefts = {
        program + version + " · " + model.socket,
        program + version + " · " + short_socket,
        program + " · " + short_socket,
        " " + short_socket,
    };
    std::vector<std::string> rights;
    if (model.uptime_ms) {
        rights.push_back(fmt::format("up {}  {} ", duration_text(*model.uptime_ms), model.clock));
    }
    rights.push_back(model.clock + " ");
    for (const auto& right : rights) {
        for (const auto& left : lefts) {
            if (fits(left, right, width)) {
                return Title{left, right};
            }
        }
    }
    // Narrower than " …/name  clock ": the name cut at its end, then no clock.
    const std::string& clock = rights.back();
    constexpr int kLeastName = 8;
    if (width - 1 - columns(clock) >= kLeastName + 1) {
        return Title{cut_end(lefts.back(), width - 1 - columns(clock), ellipsis), clock};
    }
    return Title{cut_end(lefts.back(), std::max(width - 1, 0), ellipsis), ""};
}

}  // namespace gport::cli::monitor
