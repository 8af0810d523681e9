// The token file (docs/web.md, "The token file"): one token a line,
// `control:TOKEN`, `view:TOKEN` or a bare TOKEN (control); at least 16 of
// [A-Za-z0-9_-]. It must be the user's own and readable by no one else.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gport::web {

enum class Role { kView, kControl };

std::string_view role_name(Role role);

struct Token {
    std::string secret;
    Role role = Role::kControl;
};

// The tokens of a file that was read, or was created (then `created` holds
// the new control token, for the first-run URL).
struct TokenFile {
    std::vector<Token> tokens;
    std::optional<std::string> created;
};

// Reads `path`, or creates it (mode 0600, its directory 0700 if missing)
// with one random control token. Throws std::runtime_error naming the file
// and what is wrong: another owner, a mode readable by group or others (the
// mode in octal), a bad line (its number), no token.
TokenFile load_tokens(const std::string& path);

// Parses the text of a token file; throws std::runtime_error naming the line.
std::vector<Token> parse_tokens(std::string_view text);

// The role of `secret`, compared in constant time with each token.
std::optional<Role> role_of(const std::vector<Token>& tokens, std::string_view secret);

// `bytes` random bytes from getrandom(2), as hex.
std::string random_hex(std::size_t bytes);

}  // namespace gport::web
