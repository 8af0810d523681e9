// The command-line conventions gportd, gportctl and gport-sim share, on top
// of CLI11: the same syntax (--opt VALUE, --opt=VALUE, signed numbers such as
// +30 or -12.5 as values, -h/--help, --version), the same wording of errors
// (the option, the value, what is allowed) and the same exit statuses.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gport::args {

// Sets the conventions on `app`: --help/-h, --version printing
// "<name> <version>", options after a subcommand reaching its parents,
// the last of a repeated option winning, and `exit_statuses` as the help
// footer.
void configure(CLI::App& app, std::string_view exit_statuses);

// "2s", "500ms", "1.5s", "2m", "1h" -> milliseconds (at least 1 ms); nullopt
// for anything else.
std::optional<std::chrono::milliseconds> parse_duration(std::string_view text);

// A number (a leading + allowed) within [min, max]; `what` names it in the
// error, e.g. "degrees" -> "expected degrees from -327.67 to 327.67".
CLI::Validator number_in(double min, double max, std::string what);
// An integer within [min, max].
CLI::Validator integer_in(long long min, long long max);
// A duration (parse_duration) within [min, max]; a bare number counts in
// milliseconds when `bare_ms` is true.
CLI::Validator duration_in(std::chrono::milliseconds min, std::chrono::milliseconds max,
                           bool bare_ms = false);

// One of `names`: "maybe: expected on or off" / "expected one of a, b, c".
CLI::Validator one_of(std::vector<std::string> names);

// What is wrong with the arguments CLI11 left over (the app allows extras
// so that they are named here): "unknown option --x; the options are ..."
// or "unexpected argument \"x\"; <program> takes only options". Empty when
// nothing is left.
std::string leftover_problem(const CLI::App& app);

// A CLI11 check from a function that returns the problem with a value, if any.
CLI::Validator check_with(std::function<std::optional<std::string>(std::string_view)> check);

// One line for a usage error: what CLI11 found wrong, in our words where
// CLI11's are unclear.
std::string message_of(const CLI::ParseError& error);

// True for the parse "errors" that are requests: --help, --version.
bool is_request(const CLI::ParseError& error);

}  // namespace gport::args
