#include "library/PolylineGather.h"

#include <algorithm>
#include <limits>

#include "common/QuantizedPolyline.h"

namespace mwb {

uint32_t kept_point_count(uint32_t points, uint32_t stride) {
    if (points == 0) return 0;
    const uint32_t regular = (points - 1) / stride + 1;
    // The last point is kept even when the stride steps over it.
    return (points - 1) % stride == 0 ? regular : regular + 1;
}

std::vector<uint32_t> kept_point_indices(uint32_t points, uint32_t stride) {
    std::vector<uint32_t> kept(kept_point_count(points, stride));
    for (uint32_t k = 0; k < kept.size(); ++k) kept[k] = kept_point_index(k, points, stride);
    return kept;
}

uint32_t gathered_point_count(const std::vector<const StoredWorld*>& worlds, uint32_t stride) {
    uint32_t most = 0;
    for (const StoredWorld* world : worlds) most = std::max(most, kept_point_count(world->polyline_points, stride));
    return most;
}

void gather_polylines(const std::vector<const StoredWorld*>& worlds, const std::vector<uint32_t>& bodies,
                      uint32_t stride, uint32_t points_out, float* out) {
    const size_t path_floats = size_t{points_out} * 3;
    std::fill_n(out, worlds.size() * bodies.size() * path_floats, std::numeric_limits<float>::quiet_NaN());
    for (size_t w = 0; w < worlds.size(); ++w) {
        const StoredWorld& world = *worlds[w];
        const uint32_t points = world.polyline_points;
        const uint32_t kept = kept_point_count(points, stride);
        const size_t words = quantized::block_words(points);
        const size_t tracks = points == 0 ? 0 : world.polyline.size() / words;
        for (size_t b = 0; b < bodies.size(); ++b) {
            const uint32_t body = bodies[b];
            // Absent tracks and bodies past the tracks stay NaN.
            if (body >= tracks) continue;
            const uint16_t* block = world.polyline.data() + size_t{body} * words;
            if (quantized::absent(block)) continue;
            const quantized::Header header = quantized::header(block);
            float* target = out + (w * bodies.size() + b) * path_floats;
            for (uint32_t k = 0; k < kept; ++k) {
                const Vec3 p = quantized::point(header, block, kept_point_index(k, points, stride));
                for (int a = 0; a < 3; ++a) target[size_t{k} * 3 + static_cast<size_t>(a)] = static_cast<float>(p[a]);
            }
        }
    }
}

}  // namespace mwb
