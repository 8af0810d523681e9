// The exit statuses of gportd, gportctl and gport-sim: one definition each,
// from sysexits.h where one fits, so that scripts and systemd see the same
// number for the same cause whichever program exits.
#pragma once

namespace gport {

inline constexpr int kExitOk = 0;
// A failure with no sysexits code (gportctl: the daemon answered an error).
inline constexpr int kExitFailure = 1;
// gportctl angle/center --wait: the motion ended without reaching its target
// (timeout, replaced, stop, ...).
inline constexpr int kExitNotReached = 2;
inline constexpr int kExitUsage = 64;         // EX_USAGE: bad command line
inline constexpr int kExitNoInput = 66;       // EX_NOINPUT: an input file cannot be read
inline constexpr int kExitUnavailable = 69;   // EX_UNAVAILABLE: no daemon to talk to
inline constexpr int kExitOsError = 71;       // EX_OSERR: an OS resource (pty, link) cannot be made
inline constexpr int kExitLinkNotUp = 75;     // EX_TEMPFAIL: no gimbal link (status, wait link)
inline constexpr int kExitConfig = 78;        // EX_CONFIG: the configuration is wrong
inline constexpr int kExitInterrupted = 130;  // 128 + SIGINT: stopped by Ctrl-C

}  // namespace gport
