#pragma once
// Error-bounded compression of one body's orientation track (paper §3): piecewise-linear
// interpolation in the log map, bent by a coded bulge where that makes a segment longer,
// continuous from segment to segment, with quantized, predicted, Rice-coded rotation vectors. The format is described in CodecFormat.h.
#include <cstdint>
#include <vector>

namespace mwb {

/// Compresses `frame_count` orientations `wxyz` (flat (frame_count, 4) quaternions (w, x, y, z);
/// they are normalized first, and q and -q are the same rotation). Every frame decodes to within
/// `error_max_rad` of the input, measured as the angle of the relative rotation. A segment from
/// the decoded key Q0 over L frames decodes frame j as exp(u * w + u * (1 - u) * c) * Q0,
/// u = j / L, w and c world-frame rotation vectors (c zero for straight segments). The
/// quantization step is the largest power of two not above error_max_rad. Throws
/// std::invalid_argument when a quaternion is not finite or has norm below 1e-6, or `error_max_rad` is not positive and finite or outside [2^-100, 2^41) rad.
/// `wxyz` may be null when `frame_count` is 0. Thread-safe (no shared state).
std::vector<uint8_t> encode_rotation_track(const double* wxyz, uint32_t frame_count,
                                           double error_max_rad);

}  // namespace mwb
