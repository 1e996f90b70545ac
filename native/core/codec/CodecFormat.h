#pragma once
// What position and rotation track encoders and decoders agree on: format tags, limits, and the
// exact arithmetic that reconstructs a frame from a segment. The encoder measures its error with
// these same functions, which is why the decoded error never exceeds the bound.
//
// Both tracks are bit streams (see BitWriter for the bit order) laid out as
//   tag (8 bits) | frame_count (sized uint) | step exponent e (8 bits, stored as e + 128)
//   | [position only: gravity flag (1 bit), then if set, per axis a presence bit and, if present,
//      a float32: gravity * dt^2 / 2, metres]
//   | [format 2 only: curved flag (1 bit)]
//   | start key for frame 0 | segments covering frames 1 .. frame_count - 1 | zero padding.
// The quantization step is 2^e (metres for positions, radians for rotations). The start key is a
// kind bit: 0 = quantized (3 zigzagged sized uints in steps, eighth steps in format 2; a rotation
// vector for rotations),
// 1 = raw (3 or 4 float64). A segment from frame s covers frames s + 1 .. s + L and starts from
// the decoded value at frame s. Each segment is a kind bit then:
//   fit (0): [position with gravity flag: 1 bit, quadratic term on] | [curved flag: 1 bit, bulge
//            on] | last bit (1 = runs to the end of the track, else L - 1 follows, adaptive Rice)
//            | [bulge on: 3 adaptive-Rice bulge steps] | 3 adaptive-Rice residuals of the end
//            steps against the prediction;
//   raw (1): L = 1, the exact frame value as 3 or 4 float64.
// Format 1 has no curved flag and no bulges. A fit segment's offset from its start at frame j
// (u = j / L) is u * end + u * (1 - u) * kBulgeStepRatio * bulge (+ j^2 * gravity term), in
// steps, so a bulge is the segment's sag at its middle times 4: swinging links and spinning
// bodies follow arcs that a straight segment only matches over a few frames. The end is
// predicted from the speed the previous segment ended with (predict_end_steps), which is exact
// for motion under constant acceleration and, with no bulges, is format 1's previous rate.
#include <algorithm>
#include <array>
#include <cstdint>

#include "codec/RotationMath.h"
#include "common/Math.h"

namespace mwb {

/// Error bounds of the motion codec. A decoded frame is never further than these from the input.
/// The rotation bound as a person sets it, in degrees (CodecBounds keeps radians).
constexpr double kDefaultRotationErrorDeg = 0.5;

/// Degrees to the radians of a rotation bound; the one conversion, so that the same setting
/// gives the same run hash whichever front end passed it.
constexpr double rotation_bound_rad(double degrees) { return degrees * 3.14159265358979323846 / 180; }

struct CodecBounds {
    double position_error_max_m = 0.001;  ///< Euclidean distance, metres
    double rotation_error_max_rad = rotation_bound_rad(kDefaultRotationErrorDeg);  ///< relative rotation angle
};

/// Integer steps of one segment, per axis.
using SegmentSteps = std::array<int64_t, 3>;

/// First byte of a track: kind and format version. A value is never reassigned to another meaning.
constexpr uint8_t kPositionTrackFormatV1 = 0x50;
constexpr uint8_t kRotationTrackFormatV1 = 0x52;
/// Format 2 adds curved segments (a bulge term); encoders write it, decoders read 1 and 2.
constexpr uint8_t kPositionTrackFormatV2 = 0x51;
constexpr uint8_t kRotationTrackFormatV2 = 0x53;

constexpr int kStepExponentBias = 128;
constexpr int kMinStepExponent = -100;
constexpr int kMaxStepExponent = 40;
/// Longest segment in frames; keeps integer prediction products within 64 bits.
constexpr uint32_t kMaxSegmentFrames = uint32_t{1} << 20;
/// Largest |step count| of a fit segment (per axis).
constexpr int64_t kMaxSegmentSteps = int64_t{1} << 42;
/// Largest |step count| of a quantized start key (per axis).
constexpr int64_t kMaxStartSteps = int64_t{1} << 61;
/// A bulge counts in units of this many quantization steps. Rounding a bulge moves a segment's
/// middle by at most an eighth of a unit, so it can be coarser than the end; on the bench scenes
/// 4 to 5 gave the fewest bytes (finer bulges cost more bits than they save in segments).
constexpr int64_t kBulgeStepRatio = 4;
/// Format 2 quantizes the start key this many times finer than the segments: with a coarse key,
/// the first segment would start with most of the bound spent. Costs a few bits per track.
constexpr int kStartKeyStepDivisor = 8;
/// Initial parameters of the adaptive Rice coders for segment lengths and step residuals.
constexpr unsigned kLengthRiceInitialK = 3;
constexpr unsigned kResidualRiceInitialK = 2;

/// Quantization step of the start key of a track of `format` with segment step `step`.
inline double start_key_step(int format, double step) { return format >= 2 ? step / kStartKeyStepDivisor : step; }

/// Value of a quantized vector: steps * step, per axis.
inline Vec3 dequantize(const SegmentSteps& steps, double step) {
    return {double(steps[0]) * step, double(steps[1]) * step, double(steps[2]) * step};
}

/// Orientation of a quantized start key: exp(steps * step_rad), normalized.
inline Quat rotation_from_steps(const SegmentSteps& steps, double step_rad) {
    return quat_normalized(quat_exp(dequantize(steps, step_rad)));
}

/// `steps` * `length` / `previous_length` per axis, rounded half away from zero, clamped to the
/// step limit. Pure integer arithmetic, so encoder and decoder agree on every machine. `steps`
/// are within the step limit; `length` and `previous_length` are 1..kMaxSegmentFrames.
inline SegmentSteps rescale_steps(const SegmentSteps& steps, uint32_t previous_length, uint32_t length) {
    SegmentSteps scaled{};
    for (int k = 0; k < 3; ++k) {
        const int64_t product = steps[k] * int64_t{length};
        const int64_t half = previous_length / 2;
        int64_t rounded = product >= 0 ? (product + half) / previous_length
                                       : -((-product + half) / previous_length);
        if (rounded > kMaxSegmentSteps) rounded = kMaxSegmentSteps;
        if (rounded < -kMaxSegmentSteps) rounded = -kMaxSegmentSteps;
        scaled[k] = rounded;
    }
    return scaled;
}

/// End steps and bulge of the fit segment before the one being coded; zero before the first fit
/// segment and after a raw one.
struct PreviousFit {
    SegmentSteps end{};
    SegmentSteps bulge{};
    uint32_t length = 1;
};

/// Predicted end steps of a segment of `length` frames with bulge `bulge`: it leaves its start at
/// the speed the previous segment ended with, (end - kBulgeStepRatio * bulge) / previous length
/// per frame, and its own bulge bends it. With zero bulges this is the previous rate: format 1's prediction.
inline SegmentSteps predict_end_steps(const PreviousFit& previous, uint32_t length, const SegmentSteps& bulge) {
    SegmentSteps leaving{};
    for (int k = 0; k < 3; ++k)
        leaving[k] = std::clamp(previous.end[k] - kBulgeStepRatio * previous.bulge[k], -kMaxSegmentSteps,
                                kMaxSegmentSteps);
    SegmentSteps predicted = rescale_steps(leaving, previous.length, length);
    for (int k = 0; k < 3; ++k)
        predicted[k] = std::clamp(predicted[k] - kBulgeStepRatio * bulge[k], -kMaxSegmentSteps, kMaxSegmentSteps);
    return predicted;
}

inline bool is_zero(const SegmentSteps& steps) { return steps[0] == 0 && steps[1] == 0 && steps[2] == 0; }

/// Position (metres) at frame `frame` (1..length) of a fit segment starting at `start_m`:
/// start + frame^2 * quadratic_m + u * steps * step_m + u * (1 - u) * kBulgeStepRatio * bulge *
/// step_m with u = frame / length, where `quadratic_m` is the gravity term per frame^2 (gravity * dt^2 / 2)
/// or zero. A zero bulge adds nothing, so format 1 tracks decode as they always did.
inline Vec3 position_on_segment(const Vec3& start_m, const Vec3& quadratic_m, const SegmentSteps& steps,
                                const SegmentSteps& bulge, double step_m, uint32_t length, uint32_t frame) {
    const double j = frame;
    const double fraction = j / length;
    const bool curved = !is_zero(bulge);
    const double sag = curved ? j * double(length - frame) / (double(length) * length) : 0;
    Vec3 p{};
    for (int k = 0; k < 3; ++k) {
        double offset = j * j * quadratic_m[k] + fraction * (double(steps[k]) * step_m);
        if (curved) offset += sag * (double(kBulgeStepRatio * bulge[k]) * step_m);
        p[k] = start_m[k] + offset;
    }
    return p;
}

/// Orientation at frame `frame` (1..length) of a fit segment starting at `start`:
/// exp((u * steps + u * (1 - u) * kBulgeStepRatio * bulge) * step_rad) * start, normalized, with
/// u = frame / length.
/// The rotation vector acts in the world frame (left multiplication). A zero bulge adds nothing.
inline Quat rotation_on_segment(const Quat& start, const SegmentSteps& steps, const SegmentSteps& bulge,
                                double step_rad, uint32_t length, uint32_t frame) {
    const double fraction = double(frame) / length;
    const bool curved = !is_zero(bulge);
    const double sag = curved ? double(frame) * double(length - frame) / (double(length) * length) : 0;
    Vec3 v{};
    for (int k = 0; k < 3; ++k) {
        v[k] = fraction * (double(steps[k]) * step_rad);
        if (curved) v[k] += sag * (double(kBulgeStepRatio * bulge[k]) * step_rad);
    }
    return quat_normalized(quat_multiply(quat_exp(v), start));
}

}  // namespace mwb
