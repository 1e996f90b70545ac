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

// A step of at most half the bound costs at most 0.43 of the bound in rounding (half a step on
// each axis), leaving the rest to the fit; finer steps cost more bits than they save in segments.
constexpr double kStepFraction = 0.5;
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

struct SegmentFit {
    uint32_t length = 0;
    bool raw = false;
    bool gravity = false;
    SegmentSteps steps{};
    Vec3 end_m{};  // decoded position at the last frame
    double end_error_m = 0;
};

Vec3 input_frame(const PositionInput& input, uint32_t frame) {
    const double* p = input.xyz_m + 3 * size_t{frame};
    return {p[0], p[1], p[2]};
}

// Checks one quantized candidate with the decoder's arithmetic.
std::optional<SegmentFit> check_candidate(const PositionInput& input, uint32_t start_frame,
                                          const Vec3& start_m, bool gravity, uint32_t length,
                                          const SegmentSteps& steps) {
    const Vec3 quadratic = gravity ? input.quadratic_m : Vec3{0, 0, 0};
    SegmentFit fit{length, false, gravity, steps, {}, 0};
    for (uint32_t j = 1; j <= length; ++j) {
        const Vec3 decoded = position_on_segment(start_m, quadratic, steps, input.step_m, length, j);
        const double error = norm(sub(decoded, input_frame(input, start_frame + j)));
        if (!(error <= input.tolerance_m)) return std::nullopt;
        fit.end_m = decoded;
        fit.end_error_m = error;
    }
    return fit;
}

// Fits a segment of exactly `length` frames: the linear term from least squares with the start
// fixed, from interpolating the last frame, and halfway between; each is quantized and checked.
// Of those within the bound, keeps the one ending closest to the input, which helps the next
// segment.
std::optional<SegmentFit> fit_length(const PositionInput& input, uint32_t start_frame,
                                     const Vec3& start_m, bool gravity, uint32_t length) {
    const Vec3 quadratic = gravity ? input.quadratic_m : Vec3{0, 0, 0};
    Vec3 weighted{0, 0, 0};
    double weight = 0;
    Vec3 residual{};
    for (uint32_t j = 1; j <= length; ++j) {
        const double t = j;
        residual = sub(sub(input_frame(input, start_frame + j), start_m), scale(quadratic, t * t));
        weighted = add(weighted, scale(residual, t));
        weight += t * t;
    }
    const Vec3 least_squares = scale(weighted, double(length) / weight);
    const Vec3 candidates[] = {least_squares, residual,
                               scale(add(least_squares, residual), 0.5)};
    std::optional<SegmentFit> best;
    std::optional<SegmentSteps> tried[3];
    for (int c = 0; c < 3; ++c) {
        tried[c] = quantize(candidates[c], input.step_m, kMaxSegmentSteps);
        if (!tried[c] || std::find(tried, tried + c, tried[c]) != tried + c) continue;
        auto fit = check_candidate(input, start_frame, start_m, gravity, length, *tried[c]);
        if (fit && (!best || fit->end_error_m < best->end_error_m)) best = fit;
    }
    return best;
}

std::optional<SegmentFit> longest_fit(const PositionInput& input, uint32_t start_frame,
                                      const Vec3& start_m, bool gravity) {
    const uint32_t max_length = std::min(input.frame_count - 1 - start_frame, kMaxSegmentFrames);
    return longest_greedy_fit(max_length, [&](uint32_t length) {
        return fit_length(input, start_frame, start_m, gravity, length);
    });
}

bool better(const std::optional<SegmentFit>& a, const std::optional<SegmentFit>& b) {
    if (!b) return a.has_value();
    if (!a) return false;
    if (a->length != b->length) return a->length > b->length;
    return a->end_error_m < b->end_error_m;
}

SegmentFit next_segment(const PositionInput& input, uint32_t start_frame, const Vec3& start_m) {
    std::optional<SegmentFit> best = longest_fit(input, start_frame, start_m, false);
    if (input.has_gravity) {
        auto with_gravity = longest_fit(input, start_frame, start_m, true);
        if (better(with_gravity, best)) best = with_gravity;
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
    if (auto steps = quantize(first, input.step_m, kMaxStartSteps)) {
        key.steps = *steps;
        key.position_m = dequantize(*steps, input.step_m);
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
                    uint32_t frame_count, bool any_gravity) {
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
        fit_writer.write(writer, frame + 1 == frame_count, segment.length, segment.steps);
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
    write_track_header(writer, kPositionTrackFormatV1, frame_count, exponent);
    if (frame_count == 0) {
        writer.write_bit(false);
        return writer.take_bytes();
    }
    const StartKey start = make_start_key(input);
    const std::vector<SegmentFit> segments = plan_segments(input, start.position_m);
    const bool any_gravity = std::any_of(segments.begin(), segments.end(),
                                         [](const SegmentFit& s) { return s.gravity; });
    writer.write_bit(any_gravity);
    if (any_gravity) {
        // Gravity is usually along one axis: a presence bit per axis saves two float32.
        for (double value : input.quadratic_m) {
            writer.write_bit(value != 0);
            if (value != 0) writer.write_float(static_cast<float>(value));
        }
    }
    write_start_key(writer, start);
    write_segments(writer, segments, frame_count, any_gravity);
    return writer.take_bytes();
}

}  // namespace mwb
