// What the benchmark's readers of gportd share: the attitude subscription
// they send, the `dropped` count a notification reports, and the
// nearest-rank quantile every report uses.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

namespace gport::bench {

inline constexpr std::string_view kSubscribeAttitude =
    R"({"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["attitude"]}})"
    "\n";

// The "dropped" member of an attitude notification's line, 0 if absent.
inline std::uint64_t dropped_field(std::string_view line) {
    const auto at = line.find("\"dropped\":");
    return at == std::string_view::npos ? 0 : std::strtoull(line.data() + at + 10, nullptr, 10);
}

// The q-quantile (0..1) of `values` by nearest rank; reorders them.
template <typename T>
T quantile(std::vector<T>& values, double q) {
    if (values.empty()) {
        return T{};
    }
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
    const auto index = std::min(values.size() - 1, rank == 0 ? 0 : rank - 1);
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index),
                     values.end());
    return values[index];
}

}  // namespace gport::bench
