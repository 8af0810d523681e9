// One-time login codes (docs/web.md, "Logging in at the field"): a link
// `/?code=CODE` that logs a browser in once, within kLoginCodeLifetime, so
// that the address left in the browser's history logs no one in again.
// A code is EXPIRY.NONCE.MAC: the expiry in Unix seconds, 16 random bytes,
// and the HMAC-SHA256 of both keyed with a token of the token file (the
// first 32 hex digits): gport-web at its start and `gport-web --print-url`
// make them from the file alone, and the running server checks them
// against its tokens; the role is that token's. A code used is remembered
// until it expires (in a file beside the token file when asked, so a
// restart does not make it work again).
#pragma once

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gport/web/tokens.hpp"

namespace gport::web {

using WallClock = std::chrono::system_clock;

// A new code for `token`, valid until now + kLoginCodeLifetime.
std::string make_login_code(const Token& token, WallClock::time_point now = WallClock::now());

class LoginCodes {
  public:
    // The role of a well-made code of one of `tokens` that has not expired
    // and was not used; it is used from now on. Empty otherwise.
    std::optional<Role> redeem(const std::vector<Token>& tokens, std::string_view code,
                               WallClock::time_point now = WallClock::now());
    // As Sessions::persist: the codes used, kept in `path`; the problem, or "".
    std::string persist(const std::string& path);
    std::size_t remembered() const { return used_.size(); }

  private:
    void forget_expired(WallClock::time_point now);
    std::map<std::string, std::int64_t> used_;  // nonce -> expiry (Unix seconds)
    std::string path_;
};

}  // namespace gport::web
