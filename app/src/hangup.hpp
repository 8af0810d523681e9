// SIGHUP's two meanings (docs/operations.md, "Reloading the configuration").
//
// Under systemd, and wherever gportd has no controlling terminal, SIGHUP is
// the daemon convention: re-read the configuration (`systemctl reload`,
// `kill -HUP`). Started from a terminal, gportd is a foreground program like
// any other, and the kernel (or the shell) sends SIGHUP when that terminal
// closes: it should then end, not outlive the session holding the socket.
// The two are told apart by the terminal itself: a hang-up disassociates
// every process of the session from it, so /dev/tty no longer opens; a
// `kill -HUP` while the terminal is open still reloads. Started under
// nohup (SIGHUP ignored), gportd never takes SIGHUP as a hang-up.
#pragma once

namespace gport::app {

class HangupRule {
  public:
    // Reads, before any signal handler is installed, whether gportd has a
    // controlling terminal and whether SIGHUP was ignored when it started.
    static HangupRule at_start();

    // Whether a SIGHUP received now is the terminal hanging up.
    bool is_hangup() const;

    // Whether SIGHUP can mean a hang-up at all (started from a terminal).
    bool watches_terminal() const { return watch_terminal_; }

  private:
    explicit HangupRule(bool watch_terminal) : watch_terminal_(watch_terminal) {}
    bool watch_terminal_;
};

}  // namespace gport::app
