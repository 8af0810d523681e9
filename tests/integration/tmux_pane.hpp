// A tmux session of its own (its own server socket, no config file) running
// one command in an 80×24 window, for tests that look at a terminal program
// the way a person sees it: capture-pane prints what is on the screen.
#pragma once

#include <fmt/format.h>

#include <array>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "process.hpp"

namespace gport::testing {

// 'text' for sh -c.
inline std::string shell_quote(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) {
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return quoted + "'";
}

// Runs a shell command line; its stdout, or empty when it failed.
inline std::optional<std::string> shell_output(const std::string& command) {
    FILE* pipe = ::popen((command + " 2>/dev/null").c_str(), "r");
    if (pipe == nullptr) {
        return std::nullopt;
    }
    std::string out;
    std::array<char, 4096> buffer{};
    std::size_t n = 0;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) {
        out.append(buffer.data(), n);
    }
    return ::pclose(pipe) == 0 ? std::optional(out) : std::nullopt;
}

class TmuxPane {
  public:
    // `env`: "NAME=value" entries for the pane. The pane's locale is UTF-8
    // (C.UTF-8, whatever ours is) unless `env` names LANG, LC_ALL or LC_CTYPE.
    TmuxPane(const TempDir& dir, const std::string& command, std::vector<std::string> env = {},
             int width = 80, int height = 24)
        : tmux_(fmt::format("tmux -u -f /dev/null -S {}", shell_quote(dir.file("tmux.sock")))) {
        std::string env_args;
        if (!names_locale(env)) {
            env.insert(env.begin(), {"LC_ALL=", "LC_CTYPE=", "LANG=C.UTF-8"});
        }
        for (const auto& e : env) {
            env_args += " -e " + shell_quote(e);
        }
        started_ = shell_output(fmt::format("{} new-session -d -s pane -x {} -y {}{} {}", tmux_,
                                            width, height, env_args, shell_quote(command)))
                       .has_value();
    }
    ~TmuxPane() { shell_output(tmux_ + " kill-server"); }
    TmuxPane(const TmuxPane&) = delete;
    TmuxPane& operator=(const TmuxPane&) = delete;

    bool started() const { return started_; }
    // What the screen shows, row by row (-e: with the SGR attributes).
    std::string screen(bool escapes = false) const {
        return shell_output(
                   fmt::format("{} capture-pane -p {}-t pane", tmux_, escapes ? "-e " : ""))
            .value_or("");
    }
    // Types keys (tmux key names: q, Right, Up, C-c).
    void keys(const std::string& keys) const {
        shell_output(fmt::format("{} send-keys -t pane {}", tmux_, keys));
    }
    // A tmux format about the pane, e.g. "#{alternate_on}".
    std::string format(const std::string& format) const {
        auto out = shell_output(
                       fmt::format("{} display-message -p -t pane {}", tmux_, shell_quote(format)))
                       .value_or("");
        while (!out.empty() && out.back() == '\n') {
            out.pop_back();
        }
        return out;
    }
    // Waits until the screen satisfies pred; the last screen seen goes to `last`.
    bool wait_screen(const std::function<bool(const std::string&)>& pred, std::string& last,
                     std::chrono::milliseconds timeout = 10s) const {
        return eventually(
            [&] {
                last = screen();
                return pred(last);
            },
            timeout);
    }

  private:
    static bool names_locale(const std::vector<std::string>& env) {
        for (const auto& e : env) {
            for (const char* name : {"LANG=", "LC_ALL=", "LC_CTYPE="}) {
                if (e.rfind(name, 0) == 0) {
                    return true;
                }
            }
        }
        return false;
    }

    std::string tmux_;
    bool started_ = false;
};

}  // namespace gport::testing
