#pragma once
// Encoder-side helpers shared by the position and rotation encoders (decoders never need them).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "codec/CodecFormat.h"

namespace mwb {

/// Rounds value / step to integers per axis; nullopt when any |value / step| exceeds `max_steps`.
inline std::optional<SegmentSteps> quantize(const Vec3& value, double step, int64_t max_steps) {
    SegmentSteps steps{};
    for (int k = 0; k < 3; ++k) {
        const double scaled = value[k] / step;
        if (!(std::fabs(scaled) <= double(max_steps))) return std::nullopt;
        steps[k] = std::llround(scaled);
    }
    return steps;
}

/// Greedy segment length: doubles the length while `fit_length(length)` succeeds, then bisects
/// between the last length that fit and the first that did not. Returns the fit of the longest
/// length found in 1..max_length (max_length >= 1), or nullopt when even one frame does not fit.
/// `fit_length(uint32_t)` returns std::optional<Fit>.
template <class FitLength>
auto longest_greedy_fit(uint32_t max_length, FitLength fit_length) {
    auto best = fit_length(1);
    if (!best) return best;
    uint32_t good = 1;
    uint32_t bad = 0;
    while (good < max_length) {
        const uint32_t next = std::min(2 * good, max_length);
        auto fit = fit_length(next);
        if (!fit) {
            bad = next;
            break;
        }
        best = fit;
        good = next;
    }
    while (bad > good + 1) {
        const uint32_t middle = good + (bad - good) / 2;
        auto fit = fit_length(middle);
        if (fit) {
            best = fit;
            good = middle;
        } else {
            bad = middle;
        }
    }
    return best;
}

}  // namespace mwb
