// gport-mavlink's options: the command line (CLI11) over the `mavlink`
// section of a JSON config file over the defaults (docs/mavlink.md,
// "Options"). Pure: parsing reads the config file, nothing else.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gport/client/client.hpp"
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
    std::string socket = client::Client::kDefaultSocket;
    // Loopback only: behind mavlink-router (docs/mavlink.md, "Security").
    Endpoint mavlink{Endpoint::Kind::kUdpIn, "127.0.0.1", 14560};
    std::optional<std::uint8_t> sysid = 1;      // the vehicle's; empty: `auto` (adopt)
    std::vector<std::uint8_t> gcs_sysids{255};  // ground stations whose commands we take
    std::uint8_t compid = 154;
    double attitude_rate_hz = 10;
    unsigned lease_ms = 500;
    std::string log_level = "info";
    Invert invert{};
    std::string signing_key{};  // the key file; empty: no signing
    std::string state_dir{};    // for the signing timestamp; default $STATE_DIRECTORY
    bool camera = true;         // the camera component (compid 100); --no-camera
};

// The camera component's id (MAV_COMP_ID_CAMERA), beside the gimbal's.
inline constexpr std::uint8_t kCameraCompid = 100;

// What parse_options reads from the environment.
struct Environment {
    std::string socket{};           // $GPORT_SOCKET
    std::string state_directory{};  // $STATE_DIRECTORY (systemd's StateDirectory=)
};

struct ParseOutcome {
    std::optional<Options> options{};  // set when the program should run
    int exit_code = 0;                 // else: 0 (help, version), 64 or 78
    std::string text{};                // what to print (stdout for 0, else stderr)
};

// argv as main() got it; empty strings in `env` for unset variables.
ParseOutcome parse_options(const std::vector<std::string>& argv, const Environment& env);

// "auto" (out: empty) or a system id 1 to 255; false with the error, which
// says what is allowed, for anything else.
bool parse_sysid(std::string_view text, std::optional<std::uint8_t>& out, std::string& error);
// "none" or a comma-separated list of system ids 1 to 255 ("255", "255,250").
std::optional<std::vector<std::uint8_t>> parse_sysid_list(std::string_view text,
                                                          std::string& error);
std::string to_string(const std::vector<std::uint8_t>& sysids);

}  // namespace gport::mavlink::bridge
