#include "terminal.hpp"

#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace gport::cli::monitor {
namespace {

// Alternate screen, cursor hidden, line wrap off (the bottom-right cell can
// be written without scrolling); and back.
constexpr std::string_view kEnter = "\x1b[?1049h\x1b[?25l\x1b[?7l\x1b[H\x1b[2J";
constexpr std::string_view kLeave = "\x1b[0m\x1b[?7h\x1b[?25h\x1b[?1049l";

volatile std::sig_atomic_t g_resized = 0;

void on_winch(int) {
    g_resized = 1;
}

void write_all(std::string_view bytes) noexcept {
    while (!bytes.empty()) {
        const ssize_t n = ::write(STDOUT_FILENO, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return;  // stdout is gone: nothing more to show
        }
        bytes.remove_prefix(static_cast<std::size_t>(n));
    }
}

}  // namespace

bool full_screen_possible() {
    const char* term = std::getenv("TERM");
    return ::isatty(STDOUT_FILENO) == 1 && !(term != nullptr && std::strcmp(term, "dumb") == 0);
}

Terminal::Terminal() {
    if (::isatty(STDIN_FILENO) == 1) {
        termios settings{};
        if (::tcgetattr(STDIN_FILENO, &settings) != 0) {
            throw std::runtime_error(std::string("cannot read the terminal's settings: ") +
                                     std::strerror(errno));
        }
        saved_ = settings;
        // Keys one at a time, not echoed; Ctrl-C still raises SIGINT (ISIG kept).
        settings.c_lflag &= static_cast<tcflag_t>(~(ICANON | ECHO));
        settings.c_cc[VMIN] = 0;
        settings.c_cc[VTIME] = 0;
        if (::tcsetattr(STDIN_FILENO, TCSANOW, &settings) != 0) {
            saved_.reset();
            throw std::runtime_error(std::string("cannot set the terminal's mode: ") +
                                     std::strerror(errno));
        }
    }
    struct sigaction action {};
    action.sa_handler = on_winch;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGWINCH, &action, &old_winch_);
    g_resized = 0;
    write_all(kEnter);
}

Terminal::~Terminal() {
    restore();
}

void Terminal::restore() noexcept {
    write_all(kLeave);
    if (saved_) {
        ::tcsetattr(STDIN_FILENO, TCSANOW, &*saved_);
        saved_.reset();
    }
    ::sigaction(SIGWINCH, &old_winch_, nullptr);
}

TerminalSize Terminal::size() const {
    winsize ws{};
    if (::ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0 && ws.ws_row > 0) {
        return TerminalSize{ws.ws_col, ws.ws_row};
    }
    return TerminalSize{};
}

bool Terminal::resized() {
    if (g_resized == 0) {
        return false;
    }
    g_resized = 0;
    return true;
}

std::string Terminal::read_input() {
    std::string bytes;
    if (!saved_) {
        return bytes;
    }
    char buffer[64];
    pollfd p{STDIN_FILENO, POLLIN, 0};
    while (::poll(&p, 1, 0) > 0 && (p.revents & POLLIN) != 0) {
        const ssize_t n = ::read(STDIN_FILENO, buffer, sizeof buffer);
        if (n <= 0) {
            break;
        }
        bytes.append(buffer, static_cast<std::size_t>(n));
    }
    return bytes;
}

void Terminal::write(std::string_view bytes) {
    write_all(bytes);
}

}  // namespace gport::cli::monitor
