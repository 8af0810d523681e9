#include "gport/cli/progress.hpp"

#include <fmt/format.h>

#include "gport/cli/printable.hpp"

namespace gport::cli {

using nlohmann::json;

Progress::Progress(std::ostream& out, std::chrono::milliseconds total, bool in_place)
    : out_(out), total_(total), in_place_(in_place) {}

void Progress::show(const json& attitude) {
    const auto elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_);
    const auto hall = attitude.value("hall", json::object());
    const auto angle = [&](const char* axis) {
        const auto it = hall.find(axis);
        return it != hall.end() && it->is_number() ? it->get<double>() : 0.0;
    };
    const auto line = fmt::format(
        "moving {:.1f}s of {:.1f}s  hall roll {:.2f} pitch {:.2f} yaw {:.2f} deg", elapsed.count(),
        std::chrono::duration<double>(total_).count(), angle("roll"), angle("pitch"), angle("yaw"));
    // On a terminal: back to the line's start, write it, clear what is left.
    out_ << (in_place_ ? "\r" + line + "\x1b[K" : line + "\n");
    out_.flush();
    shown_ = true;
}

void Progress::end(const json& motion, bool quiet) {
    if (in_place_ && shown_) {
        out_ << "\n";
    }
    shown_ = false;
    if (!quiet) {
        const auto reason = motion.value("reason", json());
        const auto change = motion.value("change", json("?"));
        out_ << fmt::format("ended: {}\n",
                            printable(reason.is_string()   ? reason.get<std::string>()
                                      : change.is_string() ? change.get<std::string>()
                                                           : json_line(change)));
    }
    out_.flush();
}

}  // namespace gport::cli
