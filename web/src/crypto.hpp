// SHA-256 and HMAC-SHA256 from OpenSSL's libcrypto, as lower-case hex: the
// session ids kept on disk (sessions.hpp) and the one-time login codes
// (login_codes.hpp).
#pragma once

#include <string>
#include <string_view>

namespace gport::web {

std::string sha256_hex(std::string_view data);
std::string hmac_sha256_hex(std::string_view key, std::string_view data);
// Equal strings, in a time that does not depend on where they differ.
bool same_secret(std::string_view a, std::string_view b);

}  // namespace gport::web
