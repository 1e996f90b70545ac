#pragma once
// Comparing simulated worlds frame by frame, for the refinement tests.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "sim/WorldResult.h"

namespace mwb::compare {

inline Vec3 position(const WorldResult& w, size_t body, size_t frame) {
    const double* p = &w.positions_m[(body * w.frame_count + frame) * 3];
    return {p[0], p[1], p[2]};
}

/// Every frame of `body` before `frames` (default: the shorter world's length) is bit-identical.
inline bool same_track(const WorldResult& a, const WorldResult& b, size_t body, size_t frames = SIZE_MAX) {
    frames = std::min<size_t>(frames, std::min(a.frame_count, b.frame_count));
    for (size_t f = 0; f < frames; ++f) {
        if (position(a, body, f) != position(b, body, f)) return false;
        for (int k = 0; k < 4; ++k)
            if (a.orientations[(body * a.frame_count + f) * 4 + k] != b.orientations[(body * b.frame_count + f) * 4 + k])
                return false;
    }
    return true;
}

}  // namespace mwb::compare
