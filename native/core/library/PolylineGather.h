#pragma once
// Copies chosen bodies' down-sampled paths out of many stored worlds into one array, so a caller
// that draws a few bodies of every world never copies whole polylines.
#include <cstdint>
#include <vector>

#include "library/WorldRecord.h"

namespace mwb {

/// Points a polyline of `points` points keeps at `stride` (>= 1): 0, stride, 2 stride, ... and the
/// last.
uint32_t kept_point_count(uint32_t points, uint32_t stride);
/// The k-th of those points (k < kept_point_count(points, stride)).
inline uint32_t kept_point_index(uint32_t k, uint32_t points, uint32_t stride) {
    const uint64_t at = uint64_t{k} * stride;
    return at < points ? static_cast<uint32_t>(at) : points - 1;
}
/// Every one of them, in order: how any front end thins a path (drawing, screen thinning).
std::vector<uint32_t> kept_point_indices(uint32_t points, uint32_t stride);

/// The largest kept_point_count of the worlds' polylines at `stride`.
uint32_t gathered_point_count(const std::vector<const StoredWorld*>& worlds, uint32_t stride);

/// Writes float32 (worlds, bodies, points_out, 3) to `out`: for each world and body, the
/// polyline's points 0, stride, 2 stride, ... and the last, then NaN up to points_out. Bodies the
/// world does not have (absent, or beyond its tracks) are all NaN. points_out must be at least
/// gathered_point_count(worlds, stride). Reads the worlds only: safe without the GIL.
void gather_polylines(const std::vector<const StoredWorld*>& worlds, const std::vector<uint32_t>& bodies,
                      uint32_t stride, uint32_t points_out, float* out);

}  // namespace mwb
