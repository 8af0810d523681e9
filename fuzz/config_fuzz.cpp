// libFuzzer target: arbitrary bytes as a config file. The loader must never
// crash, hang or throw; every input either loads into a Config that respects
// the documented ranges, or yields at least one error message.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "gport/config/loader.hpp"

namespace {

// The invariants the daemon relies on once a config has loaded.
bool within_documented_ranges(const gport::config::Config& c) {
    const auto& k = c.keepalive;
    const auto& l = c.link;
    return c.socket.mode <= 0777 && c.socket.line_limit >= 1024 &&
           c.socket.line_limit <= 16 * 1024 * 1024 && c.socket.max_clients >= 1 &&
           c.socket.max_clients <= 4096 && c.socket.queue_limit >= 8 &&
           c.socket.queue_limit <= 65536 && k.rate_hz >= 1.0 && k.rate_hz <= 50.0 &&
           k.default_duration <= k.max_duration && l.reconnect_initial <= l.reconnect_max &&
           c.requests.retries <= 10 && !c.serial.device.empty() && c.serial.device[0] == '/' &&
           !c.socket.path.empty() && c.socket.path[0] == '/';
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const auto result = gport::config::load_config_text(text, "fuzz.json");
    if (result.ok() ? !within_documented_ranges(*result) : result.error().messages.empty()) {
        std::abort();  // a broken invariant is a finding, like a crash
    }
    return 0;
}
