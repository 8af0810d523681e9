#include "sections.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>

#include "accounts.hpp"
#include "checks.hpp"

namespace gport::config::detail {
namespace {

// Reads `value`, found at the key path `path`, into `config`.
using FieldReader = void (*)(Reader&, const Json& value, const std::string& path, Config&);
// Checks between the keys of one section; `given` is the section as written.
using SectionCheck = void (*)(Reader&, const Json& given, const Config&);

struct Field {
    std::string_view key;
    FieldReader read;
};

struct Section {
    std::string_view key;
    std::vector<Field> fields;
    SectionCheck check = nullptr;

    std::vector<std::string_view> keys() const {
        std::vector<std::string_view> out;
        for (const auto& field : fields) {
            out.push_back(field.key);
        }
        return out;
    }
};

// The rates Linux termios has a Bxxx constant for.
constexpr std::array<unsigned, 30> kBaudRates = {
    50,     75,     110,     134,     150,     200,     300,     600,     1200,    1800,
    2400,   4800,   9600,    19200,   38400,   57600,   115200,  230400,  460800,  500000,
    576000, 921600, 1000000, 1152000, 1500000, 2000000, 2500000, 3000000, 3500000, 4000000};

constexpr std::int64_t kMiB = 1024 * 1024;
// (uid_t)-1 and (gid_t)-1 mean "no id" to chown() and friends.
constexpr std::int64_t kMaxId = 4294967294;
// Bounds the work of checking a peer against the lists on every connection.
constexpr std::size_t kMaxIds = 1024;

void read_baud(Reader& r, const Json& value, const std::string& path, Config& c) {
    // Only unsigned: nlohmann stores negative numbers as signed integers.
    if (value.is_number_unsigned()) {
        const auto rate = value.get<std::uint64_t>();
        const auto* match = std::find(kBaudRates.begin(), kBaudRates.end(), rate);
        if (match != kBaudRates.end()) {
            c.serial.baud = *match;
            return;
        }
    }
    r.error(path, fmt::format("must be one of the standard serial rates {}, got {}",
                              fmt::join(kBaudRates, ", "), describe(value)));
}

void read_mode(Reader& r, const Json& value, const std::string& path, Config& c) {
    if (value.is_string()) {
        const auto& text = value.get_ref<const std::string&>();
        const bool octal =
            !text.empty() && text.size() <= 4 &&
            std::all_of(text.begin(), text.end(), [](char ch) { return ch >= '0' && ch <= '7'; });
        const unsigned mode = octal ? static_cast<unsigned>(std::stoul(text, nullptr, 8)) : 0u;
        if (octal && mode <= 0777) {
            c.socket.mode = mode;
            return;
        }
    }
    r.error(path, fmt::format("must be an octal string from \"0000\" to \"0777\" such as "
                              "\"0660\", got {}",
                              describe(value)));
}

void read_group(Reader& r, const Json& value, const std::string& path, Config& c) {
    auto name = r.string(value, path);
    if (!name) {
        return;
    }
    if (!name->empty()) {  // empty: keep the daemon's own group
        if (auto gid = lookup_group(*name); !gid) {
            r.error(path, fmt::format("{}; give an existing group name, or \"\" to keep the "
                                      "daemon's group",
                                      gid.error().messages.front()));
            return;
        }
    }
    c.socket.group = std::move(*name);
}

// A list of ids, each a number or a name looked up with `lookup`.
template <typename Id>
void read_ids(Reader& r, const Json& value, const std::string& path, std::string_view kind,
              Result<Id> (*lookup)(const std::string&), std::vector<Id>& out) {
    if (!value.is_array() || value.size() > kMaxIds) {
        r.error(path,
                fmt::format("must be an array of at most {} {} names or numeric ids, got {}",
                            kMaxIds, kind, value.is_array() ? "a longer one" : describe(value)));
        return;
    }
    std::vector<Id> ids;
    for (std::size_t i = 0; i < value.size(); ++i) {
        const auto& item = value[i];
        const auto item_path = fmt::format("{}[{}]", path, i);
        if (item.is_number_integer()) {
            if (auto n = r.integer(item, item_path, 0, kMaxId)) {
                ids.push_back(static_cast<Id>(*n));
            }
        } else if (item.is_string()) {
            if (auto name = r.string(item, item_path)) {
                if (auto id = lookup(*name)) {
                    ids.push_back(*id);
                } else {
                    r.error(item_path, id.error().messages.front());
                }
            }
        } else {
            r.error(item_path, fmt::format("must be a {} name or a numeric id from 0 to {}, got {}",
                                           kind, kMaxId, describe(item)));
        }
    }
    out = std::move(ids);
}

// Records "a (x) must not exceed b (y)" when the lower bound passes the upper.
void check_order(Reader& r, const Json& given, std::string_view section, std::string_view low_key,
                 Millis low, std::string_view high_key, Millis high) {
    // Compare only values that passed their own checks, or the message would
    // talk about a default the user never wrote.
    const auto refused = [&](std::string_view key) {
        return r.refused(fmt::format("{}.{}", section, key));
    };
    if (low <= high || refused(low_key) || refused(high_key)) {
        return;
    }
    const auto show = [&](std::string_view key, Millis value) {
        return fmt::format("{}.{} ({}{})", section, key, value.count(),
                           given.contains(key) ? "" : ", the default");
    };
    r.error(fmt::format("{} must not exceed {}", show(low_key, low), show(high_key, high)));
}

// Reserved slots must leave at least one slot for everyone else.
void check_slots(Reader& r, const Json& given, const Config& c) {
    const auto refused = [&](std::string_view key) {
        return r.refused(fmt::format("socket.{}", key));
    };
    if (c.socket.reserved_command_slots < c.socket.max_clients ||
        refused("reserved_command_slots") || refused("max_clients")) {
        return;
    }
    r.error(fmt::format(
        "socket.reserved_command_slots ({}) must be less than socket.max_clients ({}{})",
        c.socket.reserved_command_slots, c.socket.max_clients,
        given.contains("max_clients") ? "" : ", the default"));
}

// "limits.<axis>": {"min": deg, "max": deg}, min < max.
void read_range(Reader& r, const Json& value, const std::string& path, AxisRange& out) {
    static const std::vector<std::string_view> kKeys = {"min", "max"};
    if (!r.object(value, path, kKeys)) {
        return;
    }
    AxisRange range = out;
    bool ok = true;
    for (const auto& [key, member] : value.items()) {
        const auto member_path = fmt::format("{}.{}", path, key);
        if (key == "min" || key == "max") {
            if (auto n = r.number(member, member_path, -kMaxDegrees, kMaxDegrees)) {
                (key == "min" ? range.min : range.max) = *n;
            } else {
                ok = false;
            }
        } else {
            r.unknown_key(path, key, kKeys);
            ok = false;
        }
    }
    if (!ok) {
        return;
    }
    if (range.min >= range.max) {
        r.error(path, fmt::format("min ({}{}) must be less than max ({}{})", range.min,
                                  value.contains("min") ? "" : ", the default", range.max,
                                  value.contains("max") ? "" : ", the default"));
        return;
    }
    out = range;
}

// "failsafe.<key>": one of the policies; "hold" only where `hold_ok`.
void read_failsafe(Reader& r, const Json& value, const std::string& path, bool hold_ok,
                   Failsafe& out) {
    auto text = value.is_string() ? r.string(value, path) : std::nullopt;
    if (value.is_string() && !text) {
        return;  // r.string() said why
    }
    if (text) {
        for (auto f : {Failsafe::kStop, Failsafe::kHold, Failsafe::kCenter}) {
            if (*text == to_string(f) && (hold_ok || f != Failsafe::kHold)) {
                out = f;
                return;
            }
        }
        if (*text == "hold") {
            r.error(path,
                    "must be \"stop\" or \"center\", got \"hold\": a lost link has no "
                    "recent attitude to hold");
            return;
        }
    }
    r.error(path,
            fmt::format("must be {}, got {}",
                        hold_ok ? "\"stop\", \"hold\" or \"center\"" : "\"stop\" or \"center\"",
                        describe(value)));
}

const std::vector<Section>& sections() {
    static const std::vector<Section> kSections = {
        {"serial",
         {{"device",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               auto path = r.string(v, p);
               if (auto problem = path ? check_device_path(*path) : std::nullopt) {
                   r.error(p, *problem);
               } else if (path) {
                   c.serial.device = std::move(*path);
               }
           }},
          {"baud", read_baud}}},
        {"socket",
         {{"path",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               auto path = r.string(v, p);
               if (auto problem = path ? check_socket_path(*path) : std::nullopt) {
                   r.error(p, *problem);
               } else if (path) {
                   c.socket.path = std::move(*path);
               }
           }},
          {"mode", read_mode},
          {"group", read_group},
          {"line_limit",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 1024, 16 * kMiB)) {
                   c.socket.line_limit = static_cast<std::size_t>(*n);
               }
           }},
          {"max_clients",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 1, 4096)) {
                   c.socket.max_clients = static_cast<std::size_t>(*n);
               }
           }},
          {"queue_limit",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 8, 65536)) {
                   c.socket.queue_limit = static_cast<std::size_t>(*n);
               }
           }},
          {"max_clients_per_uid",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 1, 4096)) {
                   c.socket.max_clients_per_uid = static_cast<std::size_t>(*n);
               }
           }},
          {"reserved_command_slots",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 0, 4095)) {
                   c.socket.reserved_command_slots = static_cast<std::size_t>(*n);
               }
           }},
          {"idle_timeout_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.socket.idle_timeout =
                   r.millis(v, p, 100, 86400000).value_or(c.socket.idle_timeout);
           }},
          {"max_requests_per_s",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 1, 100000)) {
                   c.socket.max_requests_per_s = static_cast<unsigned>(*n);
               }
           }}},
         check_slots},
        {"keepalive",
         {{"rate_hz",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.number(v, p, 1.0, 50.0)) {
                   c.keepalive.rate_hz = *n;
               }
           }},
          {"default_duration_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.keepalive.default_duration =
                   r.millis(v, p, 100, 600000).value_or(c.keepalive.default_duration);
           }},
          {"max_duration_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.keepalive.max_duration =
                   r.millis(v, p, 100, 600000).value_or(c.keepalive.max_duration);
           }}},
         [](Reader& r, const Json& given, const Config& c) {
             check_order(r, given, "keepalive", "default_duration_ms", c.keepalive.default_duration,
                         "max_duration_ms", c.keepalive.max_duration);
         }},
        {"link",
         {{"stale_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.link.stale_after = r.millis(v, p, 50, 60000).value_or(c.link.stale_after);
           }},
          {"reconnect_initial_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.link.reconnect_initial =
                   r.millis(v, p, 10, 60000).value_or(c.link.reconnect_initial);
           }},
          {"reconnect_max_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.link.reconnect_max = r.millis(v, p, 10, 600000).value_or(c.link.reconnect_max);
           }}},
         [](Reader& r, const Json& given, const Config& c) {
             check_order(r, given, "link", "reconnect_initial_ms", c.link.reconnect_initial,
                         "reconnect_max_ms", c.link.reconnect_max);
         }},
        {"requests",
         {{"timeout_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.requests.timeout = r.millis(v, p, 10, 10000).value_or(c.requests.timeout);
           }},
          {"retries",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 0, 10)) {
                   c.requests.retries = static_cast<unsigned>(*n);
               }
           }}}},
        {"access",
         {{"control_uids",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_ids<uid_t>(r, v, p, "user", lookup_user, c.access.control_uids);
           }},
          {"control_gids",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_ids<gid_t>(r, v, p, "group", lookup_group, c.access.control_gids);
           }},
          {"vehicle_uids",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               std::vector<uid_t> uids;
               read_ids<uid_t>(r, v, p, "user", lookup_user, uids);
               c.access.vehicle_uids = std::move(uids);
           }}}},
        {"log",
         {{"level",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               auto level = r.string(v, p);
               if (auto problem = level ? check_log_level(*level) : std::nullopt) {
                   r.error(p, *problem);
               } else if (level) {
                   c.log.level = std::move(*level);
               }
           }}}},
        {"realtime",
         {{"priority",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.integer(v, p, 0, kMaxRealtimePriority)) {
                   c.realtime.priority = static_cast<int>(*n);
               }
           }},
          {"lock_memory",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto b = r.boolean(v, p)) {
                   c.realtime.lock_memory = *b;
               }
           }}}},
        {"limits",
         {{"roll",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_range(r, v, p, c.limits.roll);
           }},
          {"pitch",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_range(r, v, p, c.limits.pitch);
           }},
          {"yaw",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_range(r, v, p, c.limits.yaw);
           }},
          {"max_speed",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               // (0, 327.67]: 0.01 °/s is the protocol's smallest non-zero speed.
               if (auto n = r.number(v, p, 0.01, kMaxDegrees)) {
                   c.limits.max_speed = *n;
               }
           }},
          {"braking_margin_deg",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               if (auto n = r.number(v, p, 0, kMaxBrakingMargin)) {
                   c.limits.braking_margin_deg = *n;
               }
           }}}},
        {"failsafe",
         {{"on_owner_gone",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_failsafe(r, v, p, true, c.failsafe.on_owner_gone);
           }},
          {"on_shutdown",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_failsafe(r, v, p, true, c.failsafe.on_shutdown);
           }},
          {"on_link_lost",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               read_failsafe(r, v, p, false, c.failsafe.on_link_lost);
           }}}},
        {"motion",
         {{"tolerance_deg",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               // 0.01°: the protocol's resolution; 10°: "reached" means little beyond.
               if (auto n = r.number(v, p, 0.01, 10.0)) {
                   c.motion.tolerance_deg = *n;
               }
           }},
          {"timeout_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.motion.timeout = r.millis(v, p, 100, 600000).value_or(c.motion.timeout);
           }},
          {"stall_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               // 0: off; else 200 ms (a few samples) to 600 s (the longest timeout).
               const auto ms = r.integer(v, p, 0, 600000);
               if (ms && *ms != 0 && *ms < 200) {
                   r.error(p, fmt::format("must be 0 (off) or an integer from 200 to 600000, got {}",
                                          *ms));
               } else if (ms) {
                   c.motion.stall = Millis(*ms);
               }
           }}}},
        {"captures",
         {{"dir",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               auto path = r.string(v, p);
               if (auto problem = path ? check_state_dir(*path) : std::nullopt) {
                   r.error(p, *problem);
               } else if (path) {
                   c.captures.dir = std::move(*path);
               }
           }},
          {"max_file_bytes",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               // 4 KiB: a few captures with their meta; 1 GiB: more than a card should hold.
               if (auto n = r.integer(v, p, 4096, 1073741824)) {
                   c.captures.max_file_bytes = static_cast<std::uint64_t>(*n);
               }
           }},
          {"keep_files",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               // 2: the current file and one rotated, so the newest index always survives.
               if (auto n = r.integer(v, p, 2, 100)) {
                   c.captures.keep_files = static_cast<int>(*n);
               }
           }}}},
        {"camera",
         {{"max_commands_per_s",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               // 0.1: one every 10 s; 1000: about what the line carries (no
               // camera takes that many; a flood then waits in gportd's queue).
               if (auto n = r.number(v, p, 0.1, 1000.0)) {
                   c.camera.max_commands_per_s = *n;
               }
           }},
          {"shutter_delay_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.camera.shutter_delay =
                   r.millis(v, p, 0, kMaxShutterDelayMs).value_or(c.camera.shutter_delay);
           }},
          {"max_position_age_ms",
           [](Reader& r, const Json& v, const std::string& p, Config& c) {
               c.camera.max_position_age =
                   r.millis(v, p, 100, 10000).value_or(c.camera.max_position_age);
           }}}},
    };
    return kSections;
}

template <typename Item>
const Item* find_by_key(const std::vector<Item>& items, std::string_view key) {
    const auto it =
        std::find_if(items.begin(), items.end(), [&](const Item& item) { return item.key == key; });
    return it == items.end() ? nullptr : &*it;
}

void read_section(Reader& r, const Section& section, const Json& value, Config& config) {
    const auto keys = section.keys();
    if (!r.object(value, section.key, keys)) {
        return;
    }
    for (const auto& [key, member] : value.items()) {
        if (const auto* field = find_by_key(section.fields, key)) {
            field->read(r, member, fmt::format("{}.{}", section.key, key), config);
        } else {
            r.unknown_key(section.key, key, keys);
        }
    }
    if (section.check != nullptr) {
        section.check(r, value, config);
    }
}

}  // namespace

void read_config(Reader& reader, const Json& root, Config& config) {
    std::vector<std::string_view> keys;
    for (const auto& section : sections()) {
        keys.push_back(section.key);
    }
    if (!reader.object(root, "", keys)) {
        return;
    }
    for (const auto& [key, value] : root.items()) {
        if (const auto* section = find_by_key(sections(), key)) {
            read_section(reader, *section, value, config);
        } else {
            reader.unknown_key("", key, keys);
        }
    }
}

}  // namespace gport::config::detail
