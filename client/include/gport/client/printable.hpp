// Text that gportd or another client supplied (a process name, a capture's
// kind, a refusal's message), made safe to print on a terminal or to put in
// a file that will be: it can hold escape sequences that would clear,
// retitle or reprogram the reader's terminal (1.8.0; gportctl prints every
// such text through it, the capture CSV's text column holds it).
#pragma once

#include <string>
#include <string_view>

#include "gport/client/export.hpp"

namespace gport::client {

// `text` with every character a terminal could act on shown visibly:
// C0 controls (U+0000-U+001F, newline and tab included) and DEL as "\x1b",
// "\x7f"; C1 controls (U+0080-U+009F, e.g. the 8-bit CSI) as "\u009b"; each
// byte that is not part of well-formed UTF-8 (RFC 3629: no overlong forms,
// no surrogates, nothing past U+10FFFF) as "\xff". Everything else, valid
// printable UTF-8 such as "für" and backslashes, is kept as it is.
GPORT_CLIENT_API std::string printable(std::string_view text);

}  // namespace gport::client
