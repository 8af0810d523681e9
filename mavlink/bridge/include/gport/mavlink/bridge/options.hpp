// gport-mavlink's options: the command line (CLI11) over the `mavlink`
// section of a JSON config file over the defaults (docs/mavlink.md,
// "Options"). Pure: parsing reads the config file, nothing else.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gport/mavlink/bridge/mapping.hpp"

namespace gport::mavlink::bridge {

// A MAVLink endpoint: udpin:ADDR:PORT, udpout:ADDR:PORT or serial:DEVICE:BAUD.
struct Endpoint {
    enum class Kind { kUdpIn, kUdpOut, kSerial };
    Kind kind = Kind::kUdpIn;
    std::string address{};  // IP address, or the serial device
    unsigned number = 0;    // UDP port, or the baud rate
};

// Parses an endpoint URL; the error names what is wrong and what is allowed.
std::optional<Endpoint> parse_endpoint(const std::string& url, std::string& error);
std::string to_string(const Endpoint& endpoint);

struct Options {
    std::string socket = "/run/gportd.sock";
    Endpoint mavlink{Endpoint::Kind::kUdpIn, "0.0.0.0", 14550};
    std::optional<std::uint8_t> sysid{};  // empty: adopt the autopilot's
    std::uint8_t compid = 154;
    double attitude_rate_hz = 10;
    unsigned lease_ms = 500;
    std::string log_level = "info";
    Invert invert{};
};

struct ParseOutcome {
    std::optional<Options> options{};  // set when the program should run
    int exit_code = 0;                 // else: 0 (help, version), 64 or 78
    std::string text{};                // what to print (stdout for 0, else stderr)
};

// argv as main() got it; `env_socket` is $GPORT_SOCKET (empty when unset).
ParseOutcome parse_options(const std::vector<std::string>& argv, const std::string& env_socket);

}  // namespace gport::mavlink::bridge
