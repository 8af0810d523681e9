// One handler per method of the client API (docs/api.md). Each validates its
// params (Params throws InvalidParams, which becomes -32602), calls the core,
// and answers with a result object or the core's error.
#include "methods.hpp"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <memory>
#include <utility>

#include "attitude_channel.hpp"
#include "capture_methods.hpp"
#include "gport/contract/names.hpp"
#include "gport/ipc/event_json.hpp"
#include "json_common.hpp"
#include "params.hpp"
#include "result_json.hpp"
#include "vehicle_json.hpp"

namespace gport::ipc::detail {
namespace {

using nlohmann::json;

Reply error_of(const daemon::CommandError& error) {
    return Reply::error(error.code, error.message);
}

// Answers a command whose result is only "the frame went out".
void answer_sent(const daemon::Outcome<daemon::Done>& outcome, const Respond& respond) {
    if (!outcome) {
        respond(error_of(outcome.error()));
        return;
    }
    respond(json{{"sent", true}});
}

void answer_controller(MethodContext& c,
                       const daemon::Outcome<std::optional<daemon::ClientInfo>>& outcome,
                       const Respond& respond) {
    if (!outcome) {
        respond(error_of(outcome.error()));
        return;
    }
    respond(controller_json(outcome.value(), c.client.info));
}

daemon::Api::SettingsCallback settings_answer(Respond respond) {
    return [respond = std::move(respond)](daemon::Outcome<daemon::Settings> outcome) {
        if (!outcome) {
            respond(error_of(outcome.error()));
            return;
        }
        respond(settings_json(outcome.value()));
    };
}

// The `attitude` method's result: the sample and its age now.
json attitude_result(const daemon::AttitudeSample& sample) {
    json result = attitude_json(sample);
    const auto age = std::chrono::steady_clock::now() - sample.received;
    result["age_ms"] = std::chrono::duration_cast<std::chrono::milliseconds>(age).count();
    return result;
}

// With `wait`, the reply (`sent`) waits for the tracked motion's end and adds
// `ended`. The core calls back later, from the loop, only if the command
// succeeded; `sent` is filled in before that.
struct Waiter {
    json sent;
    Respond respond;
};

daemon::MotionEndCallback answer_on_end(const std::shared_ptr<Waiter>& waiter) {
    return [waiter](const daemon::MotionEnd& end) {
        json result = std::move(waiter->sent);
        result["ended"] = {
            {"reason", daemon::to_string(end.reason)},
            {"attitude", end.attitude ? attitude_result(*end.attitude) : json(nullptr)},
            {"elapsed_ms", end.elapsed.count()}};
        if (!end.detail.empty()) {
            result["ended"]["detail"] = end.detail;  // stalled: where the gimbal stopped
        }
        waiter->respond(std::move(result));
    };
}

// ---- queries ----------------------------------------------------------------

void status(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    const auto& shared = c.status_cache.members(StatusCache::Clock::now(), [&c] {
        const auto text = json_text(shared_status_json(c.api.status(), c.stats()));
        return text.substr(1, text.size() - 2);  // the members, without the braces
    });
    respond(Reply::raw("{\"client\":" + json_text(client_status_json(c.client)) + "," + shared +
                       ",\"captures\":" + json_text(c.captures.status()) + "}"));
}

json range_json(const config::AxisRange& range) {
    return json{{"min", range.min}, {"max", range.max}};
}

void limits(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    const auto l = c.api.limits();
    respond(json{{"roll", range_json(l.roll)},
                 {"pitch", range_json(l.pitch)},
                 {"yaw", range_json(l.yaw)},
                 {"max_speed", l.max_speed},
                 {"braking_margin_deg", l.braking_margin_deg}});
}

void attitude(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    auto sample = c.api.latest_attitude();
    if (!sample) {
        respond(Reply::error(rpc_error::kLinkDown, "no attitude received from the gimbal yet"));
        return;
    }
    respond(attitude_result(*sample));
}

using contract::kTopics;

bool& topic_flag(Subscriptions& subs, std::string_view topic) {
    if (topic == contract::kTopicAttitude) {
        return subs.attitude;
    }
    if (topic == contract::kTopicLink) {
        return subs.link;
    }
    return topic == contract::kTopicMotion ? subs.motion : subs.capture;
}

void set_topics(Subscriptions& subs, const std::vector<std::string>& topics, bool on) {
    for (const auto& topic : topics) {
        topic_flag(subs, topic) = on;
    }
}

void subscribe(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"topics", "max_rate_hz"});
    auto topics = p.names("topics", kTopics);
    if (!topics) {
        throw InvalidParams(
            "topics is required: a non-empty array of attitude, link, motion and capture");
    }
    auto rate = p.number("max_rate_hz");
    if (rate && !(*rate >= kMinRateHz && *rate <= kMaxRateHz)) {
        throw InvalidParams(fmt::format("max_rate_hz = {} is out of range; allowed {} to {}", *rate,
                                        kMinRateHz, kMaxRateHz));
    }
    auto& subs = c.client.subscriptions;
    set_topics(subs, *topics, true);
    if (std::find(topics->begin(), topics->end(), contract::kTopicAttitude) != topics->end()) {
        subs.max_rate_hz = rate;  // each attitude subscription sets (or clears) the rate
    }
    respond(subscriptions_json(subs));
}

void unsubscribe(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"topics"});
    auto topics = p.names("topics", kTopics);
    auto& subs = c.client.subscriptions;
    set_topics(subs, topics.value_or(std::vector<std::string>(kTopics.begin(), kTopics.end())),
               false);
    if (!subs.attitude) {
        subs.max_rate_hz.reset();
    }
    respond(subscriptions_json(subs));
}

// The shared-memory attitude channel: the transport sends its descriptors
// with a connection's first reply ("descriptors":2), none with later ones;
// the server attaches them to this request's reply line at the session.
void attitude_channel(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    if (c.channel == nullptr) {
        respond(Reply::error(rpc_error::kInternal,
                             std::string(detail::kUnavailable) + "not served here"));
        return;
    }
    // A notification's reply is never sent: it must not use up the
    // connection's one set of descriptors.
    auto opened = c.channel->open_attitude_channel(c.client, !c.notification);
    if (auto* error = std::get_if<std::string>(&opened)) {
        respond(Reply::error(rpc_error::kInternal, std::string(detail::kUnavailable) + *error));
        return;
    }
    const auto& info = std::get<ChannelInfo>(opened);
    // The server has told the session whether this reply carries the
    // descriptors; the result says so to the client.
    respond(json{{"version", info.version},
                 {"slots", info.slots},
                 {"size", info.size},
                 {"published", info.published},
                 {"descriptors", info.descriptors}});
}

// ---- motion and camera ------------------------------------------------------------

void speed(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"roll", "pitch", "yaw", "duration_ms", "clamp", "lease_ms"});
    const auto axes = p.axes();
    std::optional<daemon::Millis> duration;
    // Both ranges end at keepalive.max_duration_ms, named in the refusal.
    const auto max = c.api.max_duration().count();
    if (auto ms = p.integer("duration_ms", 1, max, "keepalive.max_duration_ms")) {
        duration = daemon::Millis(*ms);
    }
    std::optional<daemon::Millis> lease;
    if (auto ms = p.integer("lease_ms", 1, max, "keepalive.max_duration_ms")) {
        lease = daemon::Millis(*ms);
    }
    const bool clamp = p.boolean("clamp").value_or(false);
    auto outcome = c.api.speed(c.client.info, axes, duration, clamp, lease);
    if (!outcome) {
        respond(error_of(outcome.error()));
        return;
    }
    respond(json{{"duration_ms", outcome->duration.count()},
                 {"ends_at", detail::epoch_seconds(outcome->ends_at)},
                 {"speed", axes_json(outcome->speed)},
                 {"clamped", outcome->clamped},
                 {"braked", outcome->braked}});
}

void stop(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    answer_sent(c.api.stop(c.client.info), respond);
}

void angle(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"roll", "pitch", "yaw", "clamp", "wait"});
    const auto axes = p.axes();
    const bool clamp = p.boolean("clamp").value_or(false);
    const bool wait = p.boolean("wait").value_or(false);
    auto waiter = wait ? std::make_shared<Waiter>(Waiter{json(), respond}) : nullptr;
    auto outcome = c.api.angle(c.client.info, axes, clamp,
                               waiter ? answer_on_end(waiter) : daemon::MotionEndCallback{});
    if (!outcome) {
        respond(error_of(outcome.error()));
        return;
    }
    json sent{{"sent", true}, {"angle", axes_json(outcome->angle)}, {"clamped", outcome->clamped}};
    if (waiter) {
        waiter->sent = std::move(sent);
        return;
    }
    respond(std::move(sent));
}

void center(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"wait"});
    const bool wait = p.boolean("wait").value_or(false);
    auto waiter = wait ? std::make_shared<Waiter>(Waiter{json(), respond}) : nullptr;
    auto outcome =
        c.api.center(c.client.info, waiter ? answer_on_end(waiter) : daemon::MotionEndCallback{});
    if (!outcome) {
        respond(error_of(outcome.error()));
        return;
    }
    json sent{{"sent", true}, {"target", axes_json(outcome->angle)}, {"clamped", outcome->clamped}};
    if (waiter) {
        waiter->sent = std::move(sent);
        return;
    }
    respond(std::move(sent));
}

void lock(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    answer_sent(c.api.lock(c.client.info), respond);
}

// ---- control and settings -------------------------------------------------------

void acquire(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    answer_controller(c, c.api.acquire(c.client.info), respond);
}

void release(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    answer_controller(c, c.api.release(c.client.info), respond);
}

void get_settings(MethodContext& c, const json& params, Respond respond) {
    Params(params).only({});
    c.api.get_settings(c.client.info, settings_answer(std::move(respond)));
}

void set_settings(MethodContext& c, const json& params, Respond respond) {
    const Params p(params);
    p.only({"dead_zone", "follow_speed", "inverted"});
    daemon::SettingsChange change;
    if (auto v = p.integer("dead_zone", 0, 255)) {
        change.dead_zone = static_cast<std::uint8_t>(*v);
    }
    if (auto v = p.integer("follow_speed", 0, 255)) {
        change.follow_speed = static_cast<std::uint8_t>(*v);
    }
    change.inverted = p.boolean("inverted");
    if (!change.dead_zone && !change.follow_speed && !change.inverted) {
        throw InvalidParams(
            "set_settings needs at least one of dead_zone, follow_speed and inverted");
    }
    c.api.set_settings(c.client.info, change, settings_answer(std::move(respond)));
}

struct Entry {
    std::string_view name;
    Handler handler;
};

constexpr std::array kMethods{
    Entry{"status", status},
    Entry{"attitude", attitude},
    Entry{"subscribe", subscribe},
    Entry{"unsubscribe", unsubscribe},
    Entry{"attitude_channel", attitude_channel},
    Entry{"speed", speed},
    Entry{"stop", stop},
    Entry{"angle", angle},
    Entry{"center", center},
    Entry{"lock", lock},
    Entry{"photo", photo},
    Entry{"record", record},
    Entry{"captures", captures},
    Entry{"acquire", acquire},
    Entry{"release", release},
    Entry{"get_settings", get_settings},
    Entry{"set_settings", set_settings},
    Entry{"limits", limits},
    Entry{"publish_vehicle", publish_vehicle},
};

// The table is the contract's list of methods, in its order.
constexpr bool same_names() {
    if (kMethods.size() != contract::kMethods.size()) {
        return false;
    }
    for (std::size_t i = 0; i < kMethods.size(); ++i) {
        if (kMethods[i].name != contract::kMethods[i]) {
            return false;
        }
    }
    return true;
}
static_assert(same_names(), "ipc's methods must be gport/contract/names.hpp's kMethods");

}  // namespace

Handler find_method(std::string_view name) {
    for (const auto& entry : kMethods) {
        if (entry.name == name) {
            return entry.handler;
        }
    }
    return nullptr;
}

std::string method_list() {
    std::string out;
    for (const auto& entry : kMethods) {
        if (!out.empty()) {
            out += ", ";
        }
        out += entry.name;
    }
    return out;
}

}  // namespace gport::ipc::detail
