#include "codec/PositionEncoder.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "codec/BitWriter.h"
#include "codec/CodecFormat.h"
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

struct PositionInput {
    const double* xyz_m;
    uint32_t frame_count;
    double step_m;
    double tolerance_m;
    bool has_gravity;
    Vec3 quadratic_m;  // gravity * dt^2 / 2, rounded to float32 as stored
};

struct StartKey {
    bool raw = false;
    SegmentSteps steps{};
    Vec3 position_m{};  // as decoded
};

// The shapes a fit segment may take, cheapest first.
enum class Shape { straight, gravity, curved };

struct SegmentFit {
    uint32_t length = 0;
    bool raw = false;
    bool gravity = false;
    bool curved = false;
    SegmentSteps steps{};
    SegmentSteps bulge{};
    Vec3 end_m{};  // decoded position at the last frame
    double end_error = 0;
};

Vec3 input_frame(const PositionInput& input, uint32_t frame) {
    const double* p = input.xyz_m + 3 * size_t{frame};
    return {p[0], p[1], p[2]};
}

// Checks one quantized candidate with the decoder's arithmetic.
std::optional<SegmentFit> check_candidate(const PositionInput& input, uint32_t start_frame,
                                          const Vec3& start_m, Shape shape, uint32_t length,
                                          const SegmentSteps& steps, const SegmentSteps& bulge) {
    const bool gravity = shape == Shape::gravity;
    const Vec3 quadratic = gravity ? input.quadratic_m : Vec3{0, 0, 0};
    // A zero bulge decodes exactly as a straight segment, which is cheaper to write.
    SegmentFit fit{length, false, gravity, !is_zero(bulge), steps, bulge, {}, 0};
    const auto error_at = [&](uint32_t j, Vec3& decoded) {
        decoded = position_on_segment(start_m, quadratic, steps, bulge, input.step_m, length, j);
        return norm(sub(decoded, input_frame(input, start_frame + j)));
    };
    fit.end_error = error_at(length, fit.end_m);
    if (!(fit.end_error <= input.tolerance_m)) return std::nullopt;
    Vec3 decoded;
    if (!inner_frames_within(length, [&](uint32_t j) { return error_at(j, decoded) <= input.tolerance_m; }))
        return std::nullopt;
    return fit;
}

// Fits a segment of exactly `length` frames of the given shape.
std::optional<SegmentFit> fit_length(const PositionInput& input, uint32_t start_frame, const Vec3& start_m,
                                     Shape shape, uint32_t length) {
    const Vec3 quadratic = shape == Shape::gravity ? input.quadratic_m : Vec3{0, 0, 0};
    SegmentSums sums;
    for (uint32_t j = 1; j <= length; ++j) {
        const double t = j;
        sums.add(t / length, sub(sub(input_frame(input, start_frame + j), start_m), scale(quadratic, t * t)));
    }
    return best_segment_candidate(sums, shape == Shape::curved, input.step_m,
                                  [&](const SegmentSteps& end, const SegmentSteps& bulge) {
                                      return check_candidate(input, start_frame, start_m, shape, length, end, bulge);
                                  });
}

// The longest segment of any shape; on equal lengths the cheaper shape, tried first. A later
// shape is only tried on lengths beyond the best so far.
SegmentFit next_segment(const PositionInput& input, uint32_t start_frame, const Vec3& start_m) {
    const uint32_t max_length = std::min(input.frame_count - 1 - start_frame, kMaxSegmentFrames);
    std::optional<SegmentFit> best;
    for (Shape shape : {Shape::straight, Shape::gravity, Shape::curved}) {
        if (shape == Shape::gravity && !input.has_gravity) continue;
        const uint32_t at_least = best ? best->length + 1 : 1;
        if (at_least > max_length) break;
        auto fit = longest_greedy_fit(
            max_length, [&](uint32_t length) { return fit_length(input, start_frame, start_m, shape, length); },
            at_least);
        if (fit) best = fit;
    }
    if (best) return *best;
    // Only reachable when a one-frame jump overflows the step range: store the frame exactly.
    SegmentFit raw;
    raw.length = 1;
    raw.raw = true;
    raw.end_m = input_frame(input, start_frame + 1);
    return raw;
}

StartKey make_start_key(const PositionInput& input) {
    const Vec3 first = input_frame(input, 0);
    StartKey key;
    const double step_m = start_key_step(2, input.step_m);
    if (auto steps = quantize(first, step_m, kMaxStartSteps)) {
        key.steps = *steps;
        key.position_m = dequantize(*steps, step_m);
        if (norm(sub(key.position_m, first)) <= input.tolerance_m) return key;
    }
    key.raw = true;
    key.position_m = first;
    return key;
}

std::vector<SegmentFit> plan_segments(const PositionInput& input, const Vec3& start_m) {
    std::vector<SegmentFit> segments;
    Vec3 position = start_m;
    for (uint32_t frame = 0; frame + 1 < input.frame_count;) {
        segments.push_back(next_segment(input, frame, position));
        frame += segments.back().length;
        position = segments.back().end_m;
    }
    return segments;
}

PositionInput make_input(const double* xyz_m, uint32_t frame_count, double frame_dt_s,
                         const Vec3& gravity_m_s2, double error_max_m, int exponent) {
    if (frame_count > 0 && xyz_m == nullptr) {
        throw std::invalid_argument("encode_position_track: null positions");
    }
    if (!std::isfinite(frame_dt_s) || frame_dt_s <= 0) {
        throw std::invalid_argument("encode_position_track: frame_dt_s must be positive and finite");
    }
    if (!std::isfinite(norm(gravity_m_s2))) {
        throw std::invalid_argument("encode_position_track: gravity must be finite");
    }
    for (size_t i = 0; i < 3 * size_t{frame_count}; ++i) {
        if (!std::isfinite(xyz_m[i])) {
            throw std::invalid_argument("encode_position_track: non-finite position");
        }
    }
    PositionInput input{xyz_m, frame_count, std::ldexp(1.0, exponent),
                        error_max_m * kToleranceFraction, false, {0, 0, 0}};
    Vec3 quadratic{};
    for (int k = 0; k < 3; ++k) {
        // The decoder sees the float32 value, so the encoder fits with exactly that.
        quadratic[k] = static_cast<float>(gravity_m_s2[k] * frame_dt_s * frame_dt_s / 2);
    }
    const double magnitude = norm(quadratic);
    if (std::isfinite(magnitude) && magnitude > 0) {
        input.has_gravity = true;
        input.quadratic_m = quadratic;
    }
    return input;
}

void write_start_key(BitWriter& writer, const StartKey& key) {
    writer.write_bit(key.raw);
    if (!key.raw) return write_start_steps(writer, key.steps);
    for (double value : key.position_m) writer.write_double(value);
}

void write_segments(BitWriter& writer, const std::vector<SegmentFit>& segments,
                    uint32_t frame_count, bool any_gravity, bool any_curved) {
    FitSegmentWriter fit_writer;
    uint32_t frame = 0;
    for (const SegmentFit& segment : segments) {
        frame += segment.length;
        writer.write_bit(segment.raw);
        if (segment.raw) {
            for (double value : segment.end_m) writer.write_double(value);
            fit_writer.reset_prediction();
            continue;
        }
        if (any_gravity) writer.write_bit(segment.gravity);
        if (any_curved) writer.write_bit(segment.curved);
        fit_writer.write(writer, frame + 1 == frame_count, segment.length, segment.steps, segment.curved,
                         segment.bulge);
    }
}

}  // namespace

std::vector<uint8_t> encode_position_track(const double* xyz_m, uint32_t frame_count,
                                           double frame_dt_s, const Vec3& gravity_m_s2,
                                           double error_max_m) {
    const int exponent = step_exponent_for(error_max_m, kStepFraction);
    const PositionInput input =
        make_input(xyz_m, frame_count, frame_dt_s, gravity_m_s2, error_max_m, exponent);

    BitWriter writer;
    write_track_header(writer, kPositionTrackFormatV2, frame_count, exponent);
    if (frame_count == 0) {
        writer.write_bit(false);
        writer.write_bit(false);
        return writer.take_bytes();
    }
    const StartKey start = make_start_key(input);
    const std::vector<SegmentFit> segments = plan_segments(input, start.position_m);
    const bool any_gravity = std::any_of(segments.begin(), segments.end(),
                                         [](const SegmentFit& s) { return s.gravity; });
    const bool any_curved = std::any_of(segments.begin(), segments.end(),
                                        [](const SegmentFit& s) { return s.curved; });
    writer.write_bit(any_gravity);
    if (any_gravity) {
        // Gravity is usually along one axis: a presence bit per axis saves two float32.
        for (double value : input.quadratic_m) {
            writer.write_bit(value != 0);
            if (value != 0) writer.write_float(static_cast<float>(value));
        }
    }
    writer.write_bit(any_curved);
    write_start_key(writer, start);
    write_segments(writer, segments, frame_count, any_gravity, any_curved);
    return writer.take_bytes();
}

}  // namespace mwb
