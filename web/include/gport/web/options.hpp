// gport-web's command line (docs/web.md, "Running it"), parsed with the
// project's conventions (gport::args).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gport::web {

struct Options {
    std::string socket;  // gportd's socket
    std::string address = "127.0.0.1";
    unsigned short port = 8790;  // 0: any free port (printed)
    std::string token_file;
    std::vector<std::string> allow_hosts;
    bool print_url = false;  // print one-time login links for the server and exit
};

struct Parsed {
    std::optional<Options> options;  // empty: help or version printed
    std::string text;                // the help or version text
};

// Parses argv (without the program name); `env` looks up the environment.
// Throws std::invalid_argument with one line for a usage error.
Parsed parse_options(std::span<const std::string> argv,
                     std::string (*env)(const char* name) = nullptr);

// The default token file: $STATE_DIRECTORY/token, else
// $HOME/.config/gport-web/token.
std::string default_token_file(std::string (*env)(const char* name));

// "ADDR:PORT" ("[::1]:8790" for IPv6); nullopt when malformed.
std::optional<std::pair<std::string, unsigned short>> parse_listen(std::string_view text);

}  // namespace gport::web
