#include "codec/RotationEncoder.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "codec/BitWriter.h"
#include "codec/CodecFormat.h"
#include "codec/RotationMath.h"
#include "codec/SegmentFitting.h"

namespace mwb {
namespace {

// A step of at most the bound costs at most 0.87 of it in rounding (half a step on each axis),
// and only where a fit lands on a quantized value; with curved segments, half that step cost
// about 6% more bytes on the bench scenes (finer steps cost more bits than they save in segments).
constexpr double kStepFraction = 1.0;
// The encoder aims slightly under the bound so that a build that rounds the reconstruction
// formula differently (e.g. with fused multiply-add) still decodes within it.
constexpr double kToleranceFraction = 1.0 - 1e-9;
constexpr double kMinInputNorm = 1e-6;
constexpr double kTwoPi = 6.283185307179586476925;

struct RotationInput {
    std::vector<Quat> frames;        // normalized input
    std::vector<Vec3> increment_sum;  // [i]: sum of log(Q_j * Q_{j-1}^-1) for j = 1..i
    double step_rad;
    double tolerance_rad;
};

struct StartKey {
    bool raw = false;
    SegmentSteps steps{};
    Quat rotation{};  // as decoded
};

struct SegmentFit {
    uint32_t length = 0;
    bool raw = false;
    bool curved = false;
    SegmentSteps steps{};
    SegmentSteps bulge{};
    Quat end{};  // decoded orientation at the last frame
    double end_error = 0;
};

// The rotation vector equivalent to `rotation_vector` (same axis, angle changed by a multiple of
// 2 pi) closest to `reference`: recovers turns of more than pi that the log map folds away.
Vec3 unwrap(const Vec3& rotation_vector, const Vec3& reference) {
    const double angle = norm(rotation_vector);
    const double reference_length = norm(reference);
    if (angle == 0 && reference_length == 0) return rotation_vector;
    const Vec3 axis = angle > 0 ? scale(rotation_vector, 1 / angle)
                                : scale(reference, 1 / reference_length);
    const double turns = std::round((dot(reference, axis) - angle) / kTwoPi);
    return scale(axis, angle + kTwoPi * turns);
}

Vec3 relative_log(const Quat& to, const Quat& from) {
    return quat_log(quat_multiply(to, quat_conjugate(from)));
}

// The angle test of rotation_angle_between, 2 atan2(s, |w|) <= tolerance, decided without the
// arctangent where s / |w| is clearly on one side of tan(tolerance / 2); the arctangent decides
// the rest, so every answer is the one it would give.
class AngleTest {
public:
    explicit AngleTest(double tolerance_rad)
        : tolerance_rad_(tolerance_rad),
          tan_half_(portable::sin(tolerance_rad / 2) / portable::cos(tolerance_rad / 2)) {}

    /// Whether `decoded` is within the tolerance of `frame`.
    bool within(const Quat& decoded, const Quat& frame) const {
        const Quat r = quat_multiply(decoded, quat_conjugate(frame));
        const double s = norm(Vec3{r[1], r[2], r[3]}), w = std::fabs(r[0]);
        if (s <= tan_half_ * w * (1 - kMargin)) return true;
        if (s >= tan_half_ * w * (1 + kMargin)) return false;
        return 2.0 * portable::atan2(s, w) <= tolerance_rad_;
    }

private:
    static constexpr double kMargin = 1e-9;  // far beyond the arctangent's few ulps
    double tolerance_rad_;
    double tan_half_;
};

// The unwrapped logs of the frames after a segment start relative to it, computed once per start
// for every length the search tries.
class RelativeLogs {
public:
    RelativeLogs(const RotationInput& input, uint32_t start_frame, const Quat& start)
        : input_(input), start_frame_(start_frame), start_(start),
          first_(relative_log(input.frames[start_frame + 1], start)) {}

    /// Frame start_frame + j, j >= 1.
    const Vec3& at(uint32_t j) {
        while (logs_.size() < j) {
            const uint32_t k = static_cast<uint32_t>(logs_.size()) + 1;
            // Summed per-frame increments tell how many whole turns the log map folded away.
            const Vec3 reference = add(first_, sub(input_.increment_sum[start_frame_ + k],
                                                   input_.increment_sum[start_frame_ + 1]));
            logs_.push_back(unwrap(relative_log(input_.frames[start_frame_ + k], start_), reference));
        }
        return logs_[j - 1];
    }

private:
    const RotationInput& input_;
    uint32_t start_frame_;
    Quat start_;
    Vec3 first_;
    std::vector<Vec3> logs_;
};

std::optional<SegmentFit> check_candidate(const RotationInput& input, const AngleTest& angle_test,
                                          uint32_t start_frame, const Quat& start, uint32_t length,
                                          const SegmentSteps& steps, const SegmentSteps& bulge) {
    // A zero bulge decodes exactly as a straight segment, which is cheaper to write.
    SegmentFit fit{length, false, !is_zero(bulge), steps, bulge, {}, 0};
    fit.end = rotation_on_segment(start, steps, bulge, input.step_rad, length, length);
    if (!angle_test.within(fit.end, input.frames[start_frame + length])) return std::nullopt;
    if (!inner_frames_within(length, [&](uint32_t j) {
            return angle_test.within(rotation_on_segment(start, steps, bulge, input.step_rad, length, j),
                                     input.frames[start_frame + j]);
        }))
        return std::nullopt;
    fit.end_error = rotation_angle_between(fit.end, input.frames[start_frame + length]);
    return fit;
}

// Fits a segment of exactly `length` frames to the unwrapped log of each frame relative to the
// start.
std::optional<SegmentFit> fit_length(const RotationInput& input, const AngleTest& angle_test, RelativeLogs& logs,
                                     uint32_t start_frame, const Quat& start, bool curved, uint32_t length) {
    SegmentSums sums;
    for (uint32_t j = 1; j <= length; ++j) sums.add(double(j) / length, logs.at(j));
    return best_segment_candidate(sums, curved, input.step_rad,
                                  [&](const SegmentSteps& end, const SegmentSteps& bulge) {
                                      return check_candidate(input, angle_test, start_frame, start, length, end, bulge);
                                  });
}

// The longest segment, straight or curved; on equal lengths the straight one, which is cheaper.
// Curved ones are only tried on lengths beyond the straight one's.
SegmentFit next_segment(const RotationInput& input, const AngleTest& angle_test, uint32_t start_frame,
                        const Quat& start) {
    const auto frame_count = static_cast<uint32_t>(input.frames.size());
    RelativeLogs logs(input, start_frame, start);
    const uint32_t max_length = std::min(frame_count - 1 - start_frame, kMaxSegmentFrames);
    std::optional<SegmentFit> best;
    for (bool curved : {false, true}) {
        const uint32_t at_least = best ? best->length + 1 : 1;
        if (at_least > max_length) break;
        auto fit = longest_greedy_fit(
            max_length,
            [&](uint32_t length) { return fit_length(input, angle_test, logs, start_frame, start, curved, length); },
            at_least);
        if (fit) best = fit;
    }
    if (best) return *best;
    // Only reachable when the step is too fine for a single frame's turn: store it exactly.
    SegmentFit raw;
    raw.length = 1;
    raw.raw = true;
    // Keep the sign continuous with the decoded track, as fit segments do.
    const Quat& q = input.frames[start_frame + 1];
    const double same_sign = start[0] * q[0] + start[1] * q[1] + start[2] * q[2] + start[3] * q[3];
    raw.end = same_sign < 0 ? Quat{-q[0], -q[1], -q[2], -q[3]} : q;
    return raw;
}

StartKey make_start_key(const RotationInput& input) {
    const Quat& first = input.frames[0];
    StartKey key;
    const double step_rad = start_key_step(2, input.step_rad);
    if (auto steps = quantize(quat_log(first), step_rad, kMaxStartSteps)) {
        key.steps = *steps;
        key.rotation = rotation_from_steps(*steps, step_rad);
        if (rotation_angle_between(key.rotation, first) <= input.tolerance_rad) return key;
    }
    key.raw = true;
    key.rotation = first;
    return key;
}

std::vector<SegmentFit> plan_segments(const RotationInput& input, const Quat& start) {
    std::vector<SegmentFit> segments;
    Quat rotation = start;
    const AngleTest angle_test(input.tolerance_rad);
    for (uint32_t frame = 0; frame + 1 < input.frames.size();) {
        segments.push_back(next_segment(input, angle_test, frame, rotation));
        frame += segments.back().length;
        rotation = segments.back().end;
    }
    return segments;
}

RotationInput make_input(const double* wxyz, uint32_t frame_count, double error_max_rad,
                         int exponent) {
    if (frame_count > 0 && wxyz == nullptr) {
        throw std::invalid_argument("encode_rotation_track: null orientations");
    }
    RotationInput input{{}, {}, std::ldexp(1.0, exponent), error_max_rad * kToleranceFraction};
    input.frames.reserve(frame_count);
    input.increment_sum.reserve(frame_count);
    for (uint32_t i = 0; i < frame_count; ++i) {
        const Quat q{wxyz[4 * size_t{i}], wxyz[4 * size_t{i} + 1], wxyz[4 * size_t{i} + 2],
                     wxyz[4 * size_t{i} + 3]};
        const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!std::isfinite(length) || length < kMinInputNorm) {
            throw std::invalid_argument("encode_rotation_track: quaternion not finite or zero");
        }
        input.frames.push_back(quat_normalized(q));
        input.increment_sum.push_back(
            i == 0 ? Vec3{0, 0, 0}
                   : add(input.increment_sum.back(),
                         relative_log(input.frames[i], input.frames[i - 1])));
    }
    return input;
}

void write_start_key(BitWriter& writer, const StartKey& key) {
    writer.write_bit(key.raw);
    if (!key.raw) return write_start_steps(writer, key.steps);
    for (double value : key.rotation) writer.write_double(value);
}

void write_segments(BitWriter& writer, const std::vector<SegmentFit>& segments,
                    uint32_t frame_count, bool any_curved) {
    FitSegmentWriter fit_writer;
    uint32_t frame = 0;
    for (const SegmentFit& segment : segments) {
        frame += segment.length;
        writer.write_bit(segment.raw);
        if (segment.raw) {
            for (double value : segment.end) writer.write_double(value);
            fit_writer.reset_prediction();
            continue;
        }
        if (any_curved) writer.write_bit(segment.curved);
        fit_writer.write(writer, frame + 1 == frame_count, segment.length, segment.steps, segment.curved,
                         segment.bulge);
    }
}

}  // namespace

std::vector<uint8_t> encode_rotation_track(const double* wxyz, uint32_t frame_count,
                                           double error_max_rad) {
    const int exponent = step_exponent_for(error_max_rad, kStepFraction);
    const RotationInput input = make_input(wxyz, frame_count, error_max_rad, exponent);

    BitWriter writer;
    write_track_header(writer, kRotationTrackFormatV2, frame_count, exponent);
    if (frame_count == 0) {
        writer.write_bit(false);
        return writer.take_bytes();
    }
    const StartKey start = make_start_key(input);
    const std::vector<SegmentFit> segments = plan_segments(input, start.rotation);
    const bool any_curved = std::any_of(segments.begin(), segments.end(),
                                        [](const SegmentFit& s) { return s.curved; });
    writer.write_bit(any_curved);
    write_start_key(writer, start);
    write_segments(writer, segments, frame_count, any_curved);
    return writer.take_bytes();
}

}  // namespace mwb
