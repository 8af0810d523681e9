#include "clock_offset.hpp"

#include <algorithm>
#include <cstdlib>

namespace gport::cli {

namespace {

struct Times {
    std::vector<std::int64_t> images, captures;  // sorted
};

Times sorted_times(const std::vector<ImageFile>& images,
                   const std::vector<PhotoCapture>& captures) {
    Times t;
    for (const auto& f : images) {
        if (f.utc_us) {
            t.images.push_back(*f.utc_us);
        }
    }
    for (const auto& c : captures) {
        t.captures.push_back(c.utc_us);
    }
    std::sort(t.images.begin(), t.images.end());
    std::sort(t.captures.begin(), t.captures.end());
    return t;
}

// The most one-to-one pairs within `window` at `offset` (image minus capture):
// the sorted two-pointer sweep, which is maximal for points on a line;
// their deltas (image minus capture minus offset) into `deltas` if given.
std::size_t pairs_at(const Times& t, std::int64_t offset, std::int64_t window,
                     std::vector<std::int64_t>* deltas) {
    std::size_t n = 0;
    for (std::size_t i = 0, c = 0; i < t.images.size() && c < t.captures.size();) {
        const auto d = t.images[i] - offset - t.captures[c];
        if (d > window) {
            ++c;
        } else if (d < -window) {
            ++i;
        } else {
            ++n, ++i, ++c;
            if (deltas) {
                deltas->push_back(d);
            }
        }
    }
    return n;
}

// How many image-capture differences fall in each window-wide bin of
// -search..search: every pair within the search counted, none kept.
std::vector<std::size_t> histogram(const Times& t, std::int64_t search, std::int64_t window) {
    std::vector<std::size_t> bins(static_cast<std::size_t>(2 * search / window + 1));
    std::size_t lo = 0;
    for (const auto image : t.images) {
        while (lo < t.captures.size() && t.captures[lo] < image - search) {
            ++lo;
        }
        for (auto c = lo; c < t.captures.size() && t.captures[c] <= image + search; ++c) {
            ++bins[static_cast<std::size_t>((image - t.captures[c] + search) / window)];
        }
    }
    return bins;
}

// The centres of the busiest bins (three bins' sum), at most `count`, no
// two within two bins of each other.
std::vector<std::int64_t> peaks(const std::vector<std::size_t>& bins, std::int64_t search,
                                std::int64_t window, std::size_t count) {
    const auto n = bins.size();
    std::vector<std::pair<std::size_t, std::size_t>> scored;  // score, bin
    for (std::size_t b = 0; b < n; ++b) {
        const auto score = bins[b] + (b > 0 ? bins[b - 1] : 0) + (b + 1 < n ? bins[b + 1] : 0);
        if (score > 0) {
            scored.emplace_back(score, b);
        }
    }
    std::sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) {
        return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    std::vector<std::size_t> taken;
    for (const auto& [score, b] : scored) {
        if (taken.size() == count) {
            break;
        }
        if (std::none_of(taken.begin(), taken.end(),
                         [b = b](std::size_t t) { return (b > t ? b - t : t - b) <= 2; })) {
            taken.push_back(b);
        }
    }
    std::vector<std::int64_t> offsets;
    for (const auto b : taken) {
        offsets.push_back(static_cast<std::int64_t>(b) * window - search + window / 2);
    }
    return offsets;
}

struct Candidate {
    std::int64_t offset;
    std::size_t pairs;
};

// `offset` moved to the median of the deltas it pairs, if that pairs more.
Candidate refined(const Times& t, std::int64_t offset, std::int64_t window) {
    std::vector<std::int64_t> deltas;
    const auto pairs = pairs_at(t, offset, window, &deltas);
    if (deltas.empty()) {
        return {offset, 0};
    }
    std::nth_element(deltas.begin(),
                     deltas.begin() + static_cast<std::ptrdiff_t>(deltas.size() / 2), deltas.end());
    const auto median = offset + deltas[deltas.size() / 2];
    const auto at_median = pairs_at(t, median, window, nullptr);
    return at_median >= pairs ? Candidate{median, at_median} : Candidate{offset, pairs};
}

// The number of candidates the histogram offers.
constexpr std::size_t kPeaks = 12;

}  // namespace

OffsetEstimate estimate_offset(const std::vector<ImageFile>& images,
                               const std::vector<PhotoCapture>& captures, std::int64_t search_us,
                               std::int64_t window_us) {
    const auto t = sorted_times(images, captures);
    OffsetEstimate e;
    e.pairs_at_given = pairs_at(t, 0, window_us, nullptr);
    std::vector<Candidate> candidates{{0, e.pairs_at_given}};
    for (const auto offset :
         peaks(histogram(t, search_us, window_us), search_us, window_us, kPeaks)) {
        candidates.push_back(refined(t, offset, window_us));
    }
    Candidate best = candidates.front();
    for (const auto& c : candidates) {
        if (c.pairs > best.pairs ||
            (c.pairs == best.pairs && std::llabs(c.offset) < std::llabs(best.offset))) {
            best = c;
        }
    }
    e.offset_us = best.offset;
    e.pairs = best.pairs;
    for (const auto& c : candidates) {
        if (best.pairs > 0 && c.pairs == best.pairs &&
            std::llabs(c.offset - best.offset) > 2 * window_us) {
            e.rival_us = c.offset;
        }
    }
    return e;
}

std::optional<HourShift> hour_shift(const std::vector<ImageFile>& images,
                                    const std::vector<std::size_t>& left,
                                    const std::vector<PhotoCapture>& captures,
                                    std::int64_t tolerance_us) {
    std::vector<std::int64_t> times;
    for (const auto& c : captures) {
        times.push_back(c.utc_us);
    }
    std::sort(times.begin(), times.end());
    auto near = [&](std::int64_t t) {
        const auto it = std::lower_bound(times.begin(), times.end(), t - tolerance_us);
        return it != times.end() && *it <= t + tolerance_us;
    };
    std::optional<HourShift> best;
    for (int hours = -14; hours <= 14; ++hours) {
        const std::int64_t shift = std::int64_t{hours} * 3600 * 1000000;
        const auto n =
            static_cast<std::size_t>(std::count_if(left.begin(), left.end(), [&](auto i) {
                return hours != 0 && images[i].utc_us && near(*images[i].utc_us - shift);
            }));
        if (n > 0 && (!best || n > best->images)) {
            best = HourShift{hours, n};
        }
    }
    return best;
}

}  // namespace gport::cli
