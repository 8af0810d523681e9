#include "gport/web/login_codes.hpp"

#include <charconv>

#include "crypto.hpp"
#include "gport/web/limits.hpp"
#include "state_file.hpp"

namespace gport::web {
namespace {

constexpr std::size_t kNonceDigits = 32;
constexpr std::size_t kMacDigits = 32;

std::int64_t unix_seconds(WallClock::time_point t) {
    return std::chrono::duration_cast<std::chrono::seconds>(t.time_since_epoch()).count();
}

std::string mac_of(const Token& token, std::string_view expiry_and_nonce) {
    return hmac_sha256_hex(token.secret, "gport-web login code " + std::string(expiry_and_nonce))
        .substr(0, kMacDigits);
}

bool all_hex(std::string_view text) {
    return text.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

struct Parts {
    std::int64_t expiry = 0;
    std::string_view nonce;
    std::string_view mac;
    std::string_view signed_part;  // EXPIRY.NONCE
};

std::optional<Parts> parts_of(std::string_view code) {
    const auto first = code.find('.');
    const auto second = code.find('.', first == std::string_view::npos ? 0 : first + 1);
    if (first == std::string_view::npos || second == std::string_view::npos) {
        return std::nullopt;
    }
    Parts parts;
    const auto [end, ec] = std::from_chars(code.data(), code.data() + first, parts.expiry);
    parts.nonce = code.substr(first + 1, second - first - 1);
    parts.mac = code.substr(second + 1);
    parts.signed_part = code.substr(0, second);
    if (ec != std::errc() || end != code.data() + first || parts.nonce.size() != kNonceDigits ||
        parts.mac.size() != kMacDigits || !all_hex(parts.nonce) || !all_hex(parts.mac)) {
        return std::nullopt;
    }
    return parts;
}

}  // namespace

std::string make_login_code(const Token& token, WallClock::time_point now) {
    const auto signed_part =
        std::to_string(unix_seconds(now + kLoginCodeLifetime)) + "." + random_hex(kNonceDigits / 2);
    return signed_part + "." + mac_of(token, signed_part);
}

std::optional<Role> LoginCodes::redeem(const std::vector<Token>& tokens, std::string_view code,
                                       WallClock::time_point now) {
    const auto parts = parts_of(code);
    const auto seconds = unix_seconds(now);
    // A code lives kLoginCodeLifetime: one that claims to live longer was
    // not made by us.
    if (!parts || parts->expiry <= seconds ||
        parts->expiry > unix_seconds(now + kLoginCodeLifetime)) {
        return std::nullopt;
    }
    std::optional<Role> role;
    for (const auto& token : tokens) {
        if (same_secret(mac_of(token, parts->signed_part), parts->mac) && !role) {
            role = token.role;
        }
    }
    forget_expired(now);
    if (!role || used_.count(std::string(parts->nonce)) > 0 ||
        used_.size() >= kMaxLoginCodesRemembered) {
        return std::nullopt;
    }
    used_[std::string(parts->nonce)] = parts->expiry;
    if (!path_.empty()) {
        std::vector<std::string> lines;
        for (const auto& [nonce, expiry] : used_) {
            lines.push_back(nonce + " " + std::to_string(expiry));
        }
        std::string problem;
        write_state_file(path_, lines, problem);
    }
    return role;
}

void LoginCodes::forget_expired(WallClock::time_point now) {
    const auto seconds = unix_seconds(now);
    std::erase_if(used_, [&](const auto& entry) { return entry.second <= seconds; });
}

std::string LoginCodes::persist(const std::string& path) {
    path_ = path;
    std::string problem;
    for (const auto& line : read_state_file(path, problem).value_or(std::vector<std::string>{})) {
        const auto space = line.find(' ');
        std::int64_t expiry = 0;
        if (space != kNonceDigits || !all_hex(line.substr(0, space)) ||
            std::from_chars(line.data() + space + 1, line.data() + line.size(), expiry).ec !=
                std::errc() ||
            used_.size() >= kMaxLoginCodesRemembered) {
            continue;
        }
        used_[line.substr(0, space)] = expiry;
    }
    forget_expired(WallClock::now());
    return problem;
}

}  // namespace gport::web
