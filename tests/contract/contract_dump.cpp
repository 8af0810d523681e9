// Prints the wire contract (gport/contract/) as one JSON object, for the
// checks of the clients that cannot include it (check_python.py):
//   {"errors": {"kParse": -32700, ...}, "topics": [...], "methods": [...],
//    "counters": [...], "limits": {"max_degrees": 327.67, ...}}
#include <iostream>
#include <nlohmann/json.hpp>

#include "gport/contract/counters.hpp"
#include "gport/contract/errors.hpp"
#include "gport/contract/limits.hpp"
#include "gport/contract/names.hpp"

int main() {
    namespace c = gport::contract;
    nlohmann::ordered_json out;
    out["errors"] = nlohmann::ordered_json::object();
#define GPORT_DUMP_ERROR(name, code, meaning) out["errors"][#name] = code;
    GPORT_CONTRACT_ERROR_CODES(GPORT_DUMP_ERROR)
#undef GPORT_DUMP_ERROR
    out["default_socket"] = c::kDefaultSocket;
    out["socket_env"] = c::kSocketEnv;
    out["topics"] = nlohmann::ordered_json::array();
    for (const auto topic : c::kTopics) {
        out["topics"].push_back(std::string(topic));
    }
    out["methods"] = nlohmann::ordered_json::array();
    for (const auto method : c::kMethods) {
        out["methods"].push_back(std::string(method));
    }
    out["counters"] = nlohmann::ordered_json::array();
#define GPORT_DUMP_COUNTER(name) out["counters"].push_back(#name);
    GPORT_CONTRACT_COUNTERS(GPORT_DUMP_COUNTER)
#undef GPORT_DUMP_COUNTER
    out["limits"] = {{"max_degrees", c::kMaxDegrees},   {"max_duration_ms", c::kMaxDurationMs},
                     {"min_rate_hz", c::kMinRateHz},    {"max_rate_hz", c::kMaxRateHz},
                     {"max_depth", c::kMaxDepth},       {"max_batch", c::kMaxBatch},
                     {"max_id_length", c::kMaxIdLength}};
    std::cout << out.dump(2) << '\n';
    return 0;
}
