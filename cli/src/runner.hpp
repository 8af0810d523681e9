// gportctl's flows on libgport-client's public Client: one call and print
// (run.cpp); watch, speed and captures --follow, which read notifications
// (run_streams.cpp). gportctl speaks JSON to the person (--json, `call`), so
// it uses the Client's JSON calls (call_json_response, on_notification_json)
// rather than its typed ones.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "gport/cli/options.hpp"
#include "gport/cli/progress.hpp"
#include "gport/cli/run.hpp"
#include "gport/client/client.hpp"

namespace gport::cli {

class Runner {
  public:
    Runner(const Invocation& inv, client::Client& gportd, std::ostream& out, std::ostream& err,
           std::function<bool()> interrupted, Terminals terminals);

    int dispatch();

  private:
    using json = nlohmann::json;

    // run.cpp: calls and what they print.
    int call_any();
    int call(const std::string& method, const json& params, json& result, json* response = nullptr);
    int refused(const json& error, const json& params);
    int failed(const client::Error& error);
    // The result as the command prints it: 0, or 69 when it does not
    // decode (said on stderr, like any reply the library cannot read).
    int print(const json& result);
    static std::optional<std::string> option_refusal(const json& error, const json& params);
    int stop_and_exit();

    // run_streams.cpp: what reads notifications.
    void notification(const json& message);
    void watched(const json& message);
    void speed_progress(const json& message);
    int pump(std::chrono::milliseconds duration);
    int watch();
    int watch_shared_memory(std::vector<std::string> topics, json& result);
    int speed_for();
    int speed_until_interrupted();
    int captures();
    int list_captures(std::uint64_t& since);
    void print_capture(const json& capture);

    const Invocation& inv_;
    client::Client& gportd_;
    std::ostream& out_;
    std::ostream& err_;
    std::function<bool()> interrupted_;
    Terminals terminals_;
    long seen_ = 0;                 // watch: notifications printed
    Progress* progress_ = nullptr;  // speed --for, while the motion runs
    bool motion_over_ = false;      // speed --for: its motion ended or was replaced
    std::vector<json> followed_;    // captures --follow: notifications not yet printed
};

}  // namespace gport::cli
