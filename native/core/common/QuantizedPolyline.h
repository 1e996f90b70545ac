#pragma once
// A polyline kept for drawing and box queries in 16 bits per coordinate within its bounding box:
// half the memory of float32, about 0.3 mm over 20 m (the stored motion itself is within 1 mm).
// A block is 12 words of header (origin and step per axis, float32; origin NaN for a body the
// world does not have) and then three words per point.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "common/Math.h"

namespace mwb::quantized {

constexpr size_t kHeaderWords = 12;

inline size_t block_words(uint32_t points) { return kHeaderWords + size_t{points} * 3; }

struct Header {
    std::array<float, 3> origin;
    std::array<float, 3> step;
};

inline Header header(const uint16_t* block) {
    Header h;
    std::memcpy(&h, block, sizeof h);
    return h;
}

inline bool absent(const uint16_t* block) { return std::isnan(header(block).origin[0]); }

/// Writes the block of a body that is not there.
inline void encode_absent(uint32_t points, uint16_t* block) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Header h{{nan, nan, nan}, {0, 0, 0}};
    std::memcpy(block, &h, sizeof h);
    std::fill_n(block + kHeaderWords, size_t{points} * 3, uint16_t{0});
}

/// Writes `points` points, read as point(k)[axis], into `block` (block_words(points) words).
template <typename PointAt>
void encode(uint32_t points, PointAt&& point, uint16_t* block) {
    Header h{};
    for (int a = 0; a < 3; ++a) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (uint32_t k = 0; k < points; ++k) {
            lo = std::min(lo, double(point(k, a)));
            hi = std::max(hi, double(point(k, a)));
        }
        h.origin[a] = points > 0 ? static_cast<float>(lo) : 0.0f;
        h.step[a] = points > 0 ? static_cast<float>((hi - h.origin[a]) / 65535.0) : 0.0f;
    }
    std::memcpy(block, &h, sizeof h);
    uint16_t* steps = block + kHeaderWords;
    for (int a = 0; a < 3; ++a) {
        const double per_step = h.step[a] > 0 ? 1 / double(h.step[a]) : 0;
        // In [0, 65535.5] after clamping: the conversion's truncation rounds to the nearest step.
        for (uint32_t k = 0; k < points; ++k) {
            const double q = (double(point(k, a)) - h.origin[a]) * per_step + 0.5;
            steps[size_t{k} * 3 + a] = static_cast<uint16_t>(std::clamp(q, 0.0, 65535.0));
        }
    }
}

/// The block of a flat (n, 3) float32 polyline.
inline std::vector<uint16_t> encode_flat(const std::vector<float>& xyz) {
    const auto points = static_cast<uint32_t>(xyz.size() / 3);
    std::vector<uint16_t> block(block_words(points));
    encode(points, [&](uint32_t k, int a) { return xyz[3 * size_t{k} + static_cast<size_t>(a)]; }, block.data());
    return block;
}

/// Point k of a block whose header is `h`, as every reader decodes it.
inline Vec3 point(const Header& h, const uint16_t* block, size_t k) {
    const uint16_t* q = block + kHeaderWords + 3 * k;
    return {double(h.origin[0]) + double(h.step[0]) * q[0], double(h.origin[1]) + double(h.step[1]) * q[1],
            double(h.origin[2]) + double(h.step[2]) * q[2]};
}

}  // namespace mwb::quantized
