#include "gport/ipc/capture_log.hpp"

#include <algorithm>

namespace gport::ipc {

using nlohmann::json;

void CaptureLog::restore(const std::vector<std::string>& lines, std::uint64_t next_index) {
    for (const auto& line : lines) {
        auto capture = json::parse(line, nullptr, false);
        if (!capture.is_object() || !capture.contains("index") ||
            !capture["index"].is_number_unsigned()) {
            continue;
        }
        next_index_ = std::max(next_index_, capture["index"].get<std::uint64_t>() + 1);
        keep(std::move(capture));
    }
    next_index_ = std::max(next_index_, next_index);
}

void CaptureLog::keep(json capture) {
    captures_.push_back(std::move(capture));
    while (captures_.size() > kept_) {
        captures_.pop_front();
    }
}

const json& CaptureLog::add(json capture) {
    json indexed = {{"index", next_index_++}};
    for (auto& [key, value] : capture.items()) {
        indexed[key] = std::move(value);
    }
    ++added_;
    keep(std::move(indexed));
    const json& stored = captures_.back();
    if (sink_ != nullptr) {
        sink_->write(stored.dump());
    }
    if (listener_) {
        listener_(stored);
    }
    return stored;
}

json CaptureLog::list(std::uint64_t since, std::size_t limit) const {
    json out = json::array();
    // Indexes are increasing: find the first at or after `since`.
    auto it = std::lower_bound(
        captures_.begin(), captures_.end(), since,
        [](const json& c, std::uint64_t i) { return c["index"].get<std::uint64_t>() < i; });
    std::uint64_t next = std::max(since, next_index_);
    for (; it != captures_.end() && out.size() < limit; ++it) {
        out.push_back(*it);
        next = (*it)["index"].get<std::uint64_t>() + 1;
    }
    return json{{"captures", std::move(out)}, {"next", next}};
}

json CaptureLog::status() const {
    json out = {{"added", added_}, {"next_index", next_index_}};
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

}  // namespace gport::ipc
