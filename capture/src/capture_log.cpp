#include "gport/capture/capture_log.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>

#include "gport/base/json_depth.hpp"

namespace gport::capture {

using nlohmann::json;

namespace {

// Compact, any invalid UTF-8 replaced: a capture's text is always valid JSON.
std::string json_text(const json& value) {
    return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

// A restored line's depth: a capture is an object holding objects (client,
// attitude.imu) and a meta, itself limited when it was taken.
constexpr std::size_t kMaxRestoreDepth = 32;

// The capture's index, if `capture` is an object with one in 1..kMaxIndex.
std::optional<std::uint64_t> index_of(const json& capture) {
    if (!capture.is_object()) {
        return std::nullopt;
    }
    const auto it = capture.find("index");
    if (it == capture.end() || !it->is_number_unsigned()) {
        return std::nullopt;
    }
    const auto index = it->get<std::uint64_t>();
    if (index < 1 || index > CaptureLog::kMaxIndex) {
        return std::nullopt;
    }
    return index;
}

}  // namespace

void CaptureLog::restore(const std::vector<std::string>& lines, std::uint64_t next_index) {
    std::map<std::uint64_t, std::string> by_index;  // sorted, each index once
    for (const auto& line : lines) {
        if (base::nested_deeper_than(line, kMaxRestoreDepth)) {
            continue;
        }
        const auto capture = json::parse(line, nullptr, false);
        if (auto index = index_of(capture)) {
            by_index.insert_or_assign(*index, json_text(capture));
        }
    }
    for (auto& [index, text] : by_index) {
        next_index_ = std::max(next_index_, index + 1);
        keep(index, std::move(text));
    }
    next_index_ = std::min(std::max(next_index_, next_index), kMaxIndex + 1);
}

void CaptureLog::keep(std::uint64_t index, std::string text) {
    kept_bytes_ += text.size();
    captures_.push_back(Kept{index, std::move(text)});
    while (captures_.size() > kept_ || (kept_bytes_ > kKeptBytes && captures_.size() > 1)) {
        kept_bytes_ -= captures_.front().text.size();
        captures_.pop_front();
    }
}

std::variant<CaptureLog::Prepared, std::string> CaptureLog::prepare(const json& capture) {
    if (sink_ != nullptr) {
        reserve_ahead();
    }
    if (next_index_ > kMaxIndex) {
        return fmt::format("the capture log has given every index up to {}; no more captures",
                           kMaxIndex);
    }
    if (sink_ != nullptr) {
        const auto durable = sink_->reserved();
        if (durable && next_index_ >= *durable) {
            const auto stats = sink_->stats();
            return fmt::format(
                "the capture log cannot make index {} durable ({}: {}); nothing was sent, so "
                "that an index is never given twice",
                next_index_, sink_->path(), stats.error.value_or("the writer is behind"));
        }
    }
    auto text = json_text(capture);  // invalid UTF-8 replaced: it always serializes
    if (!capture.is_object() || text.size() < 2) {
        return std::string("a capture must be a JSON object");
    }
    // The members without the braces: add() puts index and kind first.
    text.pop_back();
    text.erase(0, 1);
    return Prepared{std::move(text)};
}

void CaptureLog::Prepared::append(std::string_view key, const json& value) {
    body += body.empty() ? "" : ",";
    body += json_text(json(key));
    body += ':';
    body += json_text(value);
}

CaptureLog::Stored CaptureLog::add(Prepared prepared, std::string_view kind) {
    const auto index = next_index_++;
    // kind is one of gportd's own words: no escaping needed.
    std::string text = fmt::format("{{\"index\":{},\"kind\":\"{}\"{}{}}}", index, kind,
                                   prepared.body.empty() ? "" : ",", prepared.body);
    ++added_;
    keep(index, std::move(text));
    const std::string& stored = captures_.back().text;
    if (sink_ != nullptr) {
        sink_->write(stored);
        reserve_ahead();
    }
    if (listener_) {
        listener_(stored);
    }
    return {index, stored};
}

// Near the durable mark, asks for it to move (the sink dedupes; each ask
// while a write fails is a retry).
void CaptureLog::reserve_ahead() {
    const auto durable = sink_->reserved();
    if (durable && *durable - std::min(*durable, next_index_) <= kReserveWhenWithin) {
        sink_->reserve(std::min(next_index_ + kReserveAhead, kMaxIndex + 1));
    }
}

std::string CaptureLog::list(std::uint64_t since, std::size_t limit) const {
    // Indexes are increasing: find the first at or after `since`.
    auto it = std::lower_bound(captures_.begin(), captures_.end(), since,
                               [](const Kept& c, std::uint64_t i) { return c.index < i; });
    std::uint64_t next = std::max(since, next_index_);
    std::string page = "{\"captures\":[";
    std::size_t count = 0;
    for (; it != captures_.end() && count < limit; ++it, ++count) {
        if (count > 0 && page.size() + it->text.size() > kMaxPageBytes) {
            break;
        }
        if (count > 0) {
            page += ',';
        }
        page += it->text;
        next = it->index + 1;
    }
    const bool more = it != captures_.end();
    if (more) {
        next = it->index;
    }
    page += fmt::format("],\"more\":{},\"next\":{}}}", more, next);
    return page;
}

json CaptureLog::status() const {
    json out = {{"added", added_}, {"next_index", next_index_}};
    const auto reserved = sink_ != nullptr ? sink_->reserved() : std::nullopt;
    out["reserved"] = reserved ? json(*reserved) : json(nullptr);
    if (sink_ == nullptr) {
        out["file"] = nullptr;
        out["written"] = 0;
        out["dropped"] = 0;
        out["error"] = nullptr;
        return out;
    }
    const auto stats = sink_->stats();
    out["file"] = sink_->path();
    out["written"] = stats.written;
    out["dropped"] = stats.dropped;
    out["error"] = stats.error ? json(*stats.error) : json(nullptr);
    return out;
}

}  // namespace gport::capture
