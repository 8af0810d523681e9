// gportctl wait link: blocks until the gimbal's link is up, for scripts and
// units (ExecStartPre=gportctl wait link --timeout 1m). Subscribes to the
// link topic first, then asks status, so that no change falls between them;
// no polling.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "gport/cli/options.hpp"
#include "gport/client/client.hpp"

namespace gport::cli {

// Runner's call(): sends one request, prints a refusal or a lost
// connection itself, returns the exit status (0 with `result` filled).
using CallFn = std::function<int(const std::string& method, const nlohmann::json& params,
                                 nlohmann::json& result)>;

// 0 once the link is up (printing its state, or with --json the link
// object); kExitLinkNotUp when inv.timeout passes first (naming what was
// waited for on `err`); 130 on Ctrl-C; 69 when gportd goes away.
int wait_link(const Invocation& inv, client::Client& gportd, const CallFn& call,
              const std::function<bool()>& interrupted, std::ostream& out, std::ostream& err);

// Whether a status result, or a link notification's params, says "up".
bool link_up(const nlohmann::json& link);

}  // namespace gport::cli
