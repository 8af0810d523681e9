// The terminal side of the monitor: raw input without echo, the alternate
// screen, a hidden cursor, no line wrap, and window size changes (SIGWINCH).
// Everything it changes is put back by the destructor, which also runs when
// the monitor ends on a signal (the loop sees the flag and returns) or an
// exception.
#pragma once

#include <termios.h>

#include <csignal>
#include <optional>
#include <string>
#include <string_view>

namespace gport::cli::monitor {

struct TerminalSize {
    int width = 80;
    int height = 24;
};

// Whether the full-screen view can run: stdout is a terminal and $TERM is
// not "dumb".
bool full_screen_possible();

class Terminal {
  public:
    // Takes over stdout (and stdin, when it is a terminal). Throws
    // std::runtime_error when the terminal cannot be set up.
    Terminal();
    ~Terminal();
    Terminal(const Terminal&) = delete;
    Terminal& operator=(const Terminal&) = delete;

    TerminalSize size() const;
    // True once after each window size change.
    bool resized();
    // Bytes typed since the last call (empty when none or stdin is no terminal).
    std::string read_input();
    // Writes all of `bytes` to stdout.
    void write(std::string_view bytes);

  private:
    void restore() noexcept;

    std::optional<termios> saved_;  // stdin's settings, when we changed them
    struct sigaction old_winch_ {};
};

}  // namespace gport::cli::monitor
