// Text that gportd or another client supplied, made safe to print on a
// terminal (issue 30): a process name, a refusal's message, a link reason
// can hold escape sequences that would clear, retitle or reprogram the
// reader's terminal. Every such text gportctl prints goes through
// printable() (libgport-client's, gport/client/printable.hpp); its JSON
// output goes through json_line().
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace gport::cli {

// `text` with every character a terminal could act on shown visibly:
// C0 controls (U+0000-U+001F, newline and tab included) and DEL as "\x1b",
// "\x7f"; C1 controls (U+0080-U+009F, e.g. the 8-bit CSI) as "\u009b"; each
// byte that is not part of well-formed UTF-8 (RFC 3629: no overlong forms,
// no surrogates, nothing past U+10FFFF) as "\xff". Everything else, valid
// printable UTF-8 such as "für" and backslashes, is kept as it is.
std::string printable(std::string_view text);

// A JSON value as one line of compact JSON: nlohmann's dump (which escapes
// C0 controls as \u00XX), with DEL and C1 controls, which it leaves raw,
// written as \u007f and \u0080-\u009f: the same JSON value, byte-exact
// otherwise. A string that is not valid UTF-8 (never one parsed off the
// wire) has U+FFFD in its place instead of throwing.
std::string json_line(const nlohmann::json& value);

}  // namespace gport::cli
