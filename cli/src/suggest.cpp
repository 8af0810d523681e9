#include "suggest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>

namespace gport::cli {

std::size_t edit_distance(std::string_view a, std::string_view b) {
    // d[i][j]: distance between a's first i and b's first j characters.
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) {
        d[i][0] = i;
    }
    std::iota(d[0].begin(), d[0].end(), std::size_t{0});
    for (std::size_t i = 1; i <= a.size(); ++i) {
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
            }
        }
    }
    return d[a.size()][b.size()];
}

std::vector<std::string> nearest(std::string_view typed,
                                 const std::vector<std::string>& candidates) {
    // Options are compared without their dashes, which every candidate shares.
    const auto bare = [](std::string_view s) {
        return s.substr(std::min(s.find_first_not_of('-'), s.size()));
    };
    const auto word = bare(typed);
    const std::size_t allowed = word.size() <= 4 ? 1 : 2;
    if (word.size() > 64) {  // a pasted blob is no typo; keep the work bounded
        return {};
    }
    std::size_t best = allowed + 1;
    std::vector<std::string> found;
    for (const auto& candidate : candidates) {
        const auto distance = edit_distance(word, bare(candidate));
        if (distance == 0 || distance > allowed || distance > best) {
            continue;
        }
        if (distance < best) {
            best = distance;
            found.clear();
        }
        found.push_back(candidate);
    }
    return found;
}

std::string did_you_mean(std::string_view typed, const std::vector<std::string>& candidates,
                         bool quoted) {
    auto found = nearest(typed, candidates);
    if (found.empty()) {
        return {};
    }
    if (quoted) {
        for (auto& name : found) {
            name = "\"" + name + "\"";
        }
    }
    const auto last = found.back();
    found.pop_back();
    return found.empty() ? fmt::format("; did you mean {}?", last)
                         : fmt::format("; did you mean {} or {}?", fmt::join(found, ", "), last);
}

}  // namespace gport::cli
