#pragma once
// Error-bounded compression of one body's position track (paper §3): greedy piecewise-quadratic
// splines, continuous from segment to segment, whose quadratic term is zero, gravity / 2 (one bit)
// or a coded bulge (for bodies on arcs: swinging links, spinning), with quantized, predicted,
// Rice-coded terms. The format is described in CodecFormat.h.
#include <cstdint>
#include <vector>

#include "common/Math.h"

namespace mwb {

/// Compresses `frame_count` positions `xyz_m` (flat (frame_count, 3), metres) recorded every
/// `frame_dt_s` seconds. Every frame decodes within `error_max_m` of the input, measured as the
/// Euclidean 3D distance. `gravity_m_s2` (e.g. (0, 0, -9.81)) is the one quadratic term a segment
/// may use besides a coded bulge. The quantization step is the largest power of
/// two not above error_max_m.
/// Throws std::invalid_argument when a position or gravity is not finite, `frame_dt_s` or
/// `error_max_m` is not positive and finite, or `error_max_m` is outside [2^-100, 2^41) m.
/// `xyz_m` may be null when `frame_count` is 0. Thread-safe (no shared state).
std::vector<uint8_t> encode_position_track(const double* xyz_m, uint32_t frame_count,
                                           double frame_dt_s, const Vec3& gravity_m_s2,
                                           double error_max_m);

}  // namespace mwb
