#pragma once
// What position and rotation track encoders and decoders agree on: format tags, limits, and the
// exact arithmetic that reconstructs a frame from a segment. The encoder measures its error with
// these same functions, which is why the decoded error never exceeds the bound.
//
// Both tracks are bit streams (see BitWriter for the bit order) laid out as
//   tag (8 bits) | frame_count (sized uint) | step exponent e (8 bits, stored as e + 128)
//   | [position only: gravity flag (1 bit), then if set, per axis a presence bit and, if present,
//      a float32: gravity * dt^2 / 2, metres]
//   | start key for frame 0 | segments covering frames 1 .. frame_count - 1 | zero padding.
// The quantization step is 2^e (metres for positions, radians for rotations). The start key is a
// kind bit: 0 = quantized (3 zigzagged sized uints in steps; a rotation vector for rotations),
// 1 = raw (3 or 4 float64). A segment from frame s covers frames s + 1 .. s + L and starts from
// the decoded value at frame s. Each segment is a kind bit then:
//   fit (0): [position with gravity flag: 1 bit, quadratic term on] | last bit (1 = runs to the
//            end of the track, else L - 1 follows, adaptive Rice) | 3 adaptive-Rice residuals of
//            the integer steps against the previous fit segment's steps scaled by L / L_prev;
//   raw (1): L = 1, the exact frame value as 3 or 4 float64.
#include <array>
#include <cstdint>

#include "codec/RotationMath.h"
#include "common/Math.h"

namespace mwb {

/// Error bounds of the motion codec. A decoded frame is never further than these from the input.
struct CodecBounds {
    double position_error_max_m = 0.001;  ///< Euclidean distance, metres
    double rotation_error_max_rad = 0.5 * 3.14159265358979323846 / 180;  ///< relative rotation angle
};

/// Integer steps of one segment, per axis.
using SegmentSteps = std::array<int64_t, 3>;

/// First byte of a track: kind and format version. A value is never reassigned to another meaning.
constexpr uint8_t kPositionTrackFormatV1 = 0x50;
constexpr uint8_t kRotationTrackFormatV1 = 0x52;

constexpr int kStepExponentBias = 128;
constexpr int kMinStepExponent = -100;
constexpr int kMaxStepExponent = 40;
/// Longest segment in frames; keeps integer prediction products within 64 bits.
constexpr uint32_t kMaxSegmentFrames = uint32_t{1} << 20;
/// Largest |step count| of a fit segment (per axis).
constexpr int64_t kMaxSegmentSteps = int64_t{1} << 42;
/// Largest |step count| of a quantized start key (per axis).
constexpr int64_t kMaxStartSteps = int64_t{1} << 61;
/// Initial parameters of the adaptive Rice coders for segment lengths and step residuals.
constexpr unsigned kLengthRiceInitialK = 3;
constexpr unsigned kResidualRiceInitialK = 2;

/// Value of a quantized vector: steps * step, per axis.
inline Vec3 dequantize(const SegmentSteps& steps, double step) {
    return {double(steps[0]) * step, double(steps[1]) * step, double(steps[2]) * step};
}

/// Orientation of a quantized start key: exp(steps * step_rad), normalized.
inline Quat rotation_from_steps(const SegmentSteps& steps, double step_rad) {
    return quat_normalized(quat_exp(dequantize(steps, step_rad)));
}

/// Prediction of a segment's steps from the previous fit segment's: the same rate per frame,
/// rounded half away from zero, clamped to the step limit. Pure integer arithmetic, so encoder and
/// decoder agree on every machine. Before the first fit segment, and after a raw one, the previous
/// steps are zero. `length` and `previous_length` are 1..kMaxSegmentFrames.
inline SegmentSteps predict_segment_steps(const SegmentSteps& previous, uint32_t previous_length,
                                          uint32_t length) {
    SegmentSteps predicted{};
    for (int k = 0; k < 3; ++k) {
        const int64_t product = previous[k] * int64_t{length};
        const int64_t half = previous_length / 2;
        int64_t rounded = product >= 0 ? (product + half) / previous_length
                                       : -((-product + half) / previous_length);
        if (rounded > kMaxSegmentSteps) rounded = kMaxSegmentSteps;
        if (rounded < -kMaxSegmentSteps) rounded = -kMaxSegmentSteps;
        predicted[k] = rounded;
    }
    return predicted;
}

/// Position (metres) at frame `frame` (1..length) of a fit segment starting at `start_m`:
/// start + frame^2 * quadratic_m + frame / length * steps * step_m, where `quadratic_m` is the
/// gravity term per frame^2 (gravity * dt^2 / 2) or zero.
inline Vec3 position_on_segment(const Vec3& start_m, const Vec3& quadratic_m,
                                const SegmentSteps& steps, double step_m, uint32_t length,
                                uint32_t frame) {
    const double j = frame;
    const double fraction = j / length;
    Vec3 p{};
    for (int k = 0; k < 3; ++k) {
        p[k] = start_m[k] + (j * j * quadratic_m[k] + fraction * (double(steps[k]) * step_m));
    }
    return p;
}

/// Orientation at frame `frame` (1..length) of a fit segment starting at `start`:
/// exp(frame / length * steps * step_rad) * start, normalized. The rotation vector acts in the
/// world frame (left multiplication).
inline Quat rotation_on_segment(const Quat& start, const SegmentSteps& steps, double step_rad,
                                uint32_t length, uint32_t frame) {
    const double fraction = double(frame) / length;
    const Vec3 v{fraction * (double(steps[0]) * step_rad), fraction * (double(steps[1]) * step_rad),
                 fraction * (double(steps[2]) * step_rad)};
    return quat_normalized(quat_multiply(quat_exp(v), start));
}

}  // namespace mwb
