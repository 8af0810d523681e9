#include "parse.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "checks.hpp"

namespace gport::config::detail {
namespace {

// Follows the parser's events to report keys given twice in one object.
// nlohmann calls the callback for every key, also in nested containers.
class DuplicateKeys {
  public:
    explicit DuplicateKeys(Reader& reader) : reader_(reader) {}

    bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
        using Event = Json::parse_event_t;
        switch (event) {
            case Event::object_start:
            case Event::array_start:
                open(event == Event::object_start);
                break;
            case Event::object_end:
            case Event::array_end:
                if (!frames_.empty()) {
                    frames_.pop_back();
                }
                break;
            case Event::key:
                key(parsed.get<std::string>());
                break;
            case Event::value:
                break;
        }
        return true;  // keep everything: this only observes
    }

  private:
    struct Frame {
        bool object = false;
        std::string path;  // e.g. "serial", "access.control_uids[]"
        std::set<std::string> keys;
    };

    // The path of the value being parsed right now in the innermost container.
    std::string current_path() const {
        if (frames_.empty()) {
            return {};
        }
        const Frame& top = frames_.back();
        if (!top.object) {
            return top.path + "[]";
        }
        return top.path.empty() ? last_key_ : top.path + "." + last_key_;
    }

    void open(bool object) { frames_.push_back(Frame{object, current_path(), {}}); }

    void key(const std::string& name) {
        last_key_ = name;
        if (frames_.empty() || !frames_.back().object) {
            return;
        }
        if (!frames_.back().keys.insert(name).second) {
            reader_.error(fmt::format("key {} appears more than once; give each key once",
                                      json_quoted(current_path())));
        }
    }

    Reader& reader_;
    std::vector<Frame> frames_;
    std::string last_key_;
};

// nlohmann's messages read "[json.exception.parse_error.101] parse error at
// line L, column C: <what went wrong>"; keep only what went wrong, since the
// location is reported in our own format.
std::string syntax_detail(std::string_view what) {
    if (what.starts_with("[json.exception.")) {
        if (const auto end = what.find("] "); end != std::string_view::npos) {
            what.remove_prefix(end + 2);
        }
    }
    if (what.starts_with("parse error")) {
        if (const auto colon = what.find(": "); colon != std::string_view::npos) {
            what.remove_prefix(colon + 2);
        }
    }
    return std::string(what);
}

// Line and column (both from 1) of the 1-based byte offset `byte`.
std::pair<std::size_t, std::size_t> line_and_column(std::string_view text, std::size_t byte) {
    const auto end = std::min(byte == 0 ? 0 : byte - 1, text.size());
    const auto before = text.substr(0, end);
    const auto line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const auto line_start = before.rfind('\n');
    const auto column = line_start == std::string_view::npos ? end + 1 : end - line_start;
    return {line, column};
}

}  // namespace

std::optional<Json> parse_json(std::string_view text, Reader& reader) {
    DuplicateKeys duplicates(reader);
    try {
        return Json::parse(text.begin(), text.end(), std::ref(duplicates),
                           /*allow_exceptions=*/true, /*ignore_comments=*/true);
    } catch (const Json::parse_error& e) {
        const auto [line, column] = line_and_column(text, e.byte);
        reader.error(fmt::format("line {}, column {} (byte {}): invalid JSON: {}", line, column,
                                 e.byte, syntax_detail(e.what())));
        return std::nullopt;
    } catch (const Json::exception& e) {  // e.g. a number too large for a double
        reader.error(fmt::format("invalid JSON: {}", syntax_detail(e.what())));
        return std::nullopt;
    }
}

}  // namespace gport::config::detail
