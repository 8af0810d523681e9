// "Did you mean ...?" for gportctl's commands and options: the candidates
// closest to a typo by edit distance, as git suggests commands.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace gport::cli {

// Optimal string alignment distance: insertions, deletions, substitutions
// and swaps of two neighbours (stauts -> status) each count 1.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidates nearest to `typed`, if near enough to be a typo: at most 1
// edit for words of up to 4 characters, 2 for longer ones; ties all kept,
// in the candidates' order. Empty when none is near.
std::vector<std::string> nearest(std::string_view typed,
                                 const std::vector<std::string>& candidates);

// "; did you mean \"status\"?" / "; did you mean --yaw or --yw?" or "".
std::string did_you_mean(std::string_view typed, const std::vector<std::string>& candidates,
                         bool quoted);

}  // namespace gport::cli
