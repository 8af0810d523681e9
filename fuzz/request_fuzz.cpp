// Fuzzes the JSON-RPC request layer: arbitrary bytes, split into lines, go
// through the dispatcher with a fake core. Every reply must be one line of
// valid JSON; nothing may crash, leak or recurse without bound.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string_view>

#include "fake_api.hpp"
#include "gport/ipc/json_rpc.hpp"

namespace {

void check_reply(const std::string& line) {
    if (line.empty() || line.back() != '\n' || line.find('\n') != line.size() - 1) {
        std::abort();  // a reply must be exactly one line
    }
    auto parsed = nlohmann::json::parse(line, nullptr, false);
    if (parsed.is_discarded() || !(parsed.is_object() || parsed.is_array())) {
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    gport::testing::FakeApi api;
    if (size > 0 && (data[0] & 0x80) != 0) {
        // Half the inputs see a core that refuses everything.
        api.error = gport::daemon::CommandError{gport::daemon::ErrorCode::kBusy, "busy"};
    }
    gport::ipc::Dispatcher dispatcher(api, [] { return gport::ipc::ServerStats{1, 0}; });
    gport::ipc::ClientState client{{1, 100, 1000, 1000, {}}, {}, 0, {}};
    const gport::ipc::ReplySink sink = [](std::string line) { check_reply(line); };

    std::string_view input(reinterpret_cast<const char*>(data), size);
    while (!input.empty()) {
        const auto newline = input.find('\n');
        dispatcher.handle_line(input.substr(0, newline), client, sink);
        if (newline == std::string_view::npos) {
            break;
        }
        input.remove_prefix(newline + 1);
    }
    api.run_settings();             // the asynchronous answers, after the lines as on the loop
    while (!api.waiters.empty()) {  // and the replies of angle/center with wait
        api.end_waiter({gport::daemon::EndReason::kReached, std::nullopt, {}});
    }
    return 0;
}
