// The capture log's JSON (codec.hpp): captures' params, its pages and the
// capture topic's notifications (docs/api.md, "Captures").
#include <algorithm>

#include "codec.hpp"

namespace gport::client::codec {

json captures_params(std::uint64_t since, std::optional<std::uint32_t> limit) {
    json params = {{"since", since}};
    if (limit) {
        params["limit"] = *limit;
    }
    return params;
}

CaptureEntry capture_entry(const json& capture) {
    if (!capture.is_object()) {
        throw Error(ErrorCode::kBadReply, "capture: expected a JSON object from gportd");
    }
    const auto report = photo_report(json{{"capture", capture}});
    CaptureEntry entry;
    entry.capture = report.capture.value_or(Capture{});
    entry.attitude = report.attitude;
    if (const auto meta = capture.find("meta"); meta != capture.end() && meta->is_object()) {
        entry.meta = meta->dump();
    }
    if (const auto peer = capture.find("client"); peer != capture.end() && peer->is_object()) {
        entry.client =
            Peer{peer->value("id", std::int64_t{0}), peer->value("pid", std::int64_t{0}),
                 peer->value("uid", std::int64_t{0}), peer->value("gid", std::int64_t{0})};
        const auto name = peer->value("name", json());
        entry.client_name = name.is_string() ? name.get<std::string>() : std::string();
    }
    return entry;
}

// `more` as gportd says; a gportd before byte-bounded pages has none: more
// while pages are not empty. Never more when `next` does not advance, so a
// caller paging on it cannot loop for ever.
CapturesPage captures_page(const json& result, std::uint64_t since) {
    if (!result.is_object() || !result.contains("captures") || !result["captures"].is_array()) {
        throw Error(ErrorCode::kBadReply, "captures result: expected {\"captures\":[...]}");
    }
    CapturesPage page;
    for (const auto& capture : result["captures"]) {
        page.captures.push_back(capture_entry(capture));
    }
    const auto next = result.value("next", json());
    page.next = next.is_number_unsigned() ? next.get<std::uint64_t>() : since;
    const auto more = result.value("more", json());
    page.more =
        (more.is_boolean() ? more.get<bool>() : !page.captures.empty()) && page.next > since;
    return page;
}

std::optional<CaptureEntry> capture_notification(const json& message) {
    if (message.value("method", json()) != "capture") {
        return std::nullopt;
    }
    return capture_entry(message.value("params", json()));
}

}  // namespace gport::client::codec
