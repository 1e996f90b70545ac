#pragma once
// Encoder-side pieces shared by the position and rotation encoders: segment search, quantization
// and the writing counterpart of TrackReading.h. Decoders never include this file.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <utility>

#include "codec/BitWriter.h"
#include "codec/CodecFormat.h"
#include "codec/RiceCode.h"

namespace mwb {

/// Rounds value / step to integers per axis; nullopt when any |value / step| exceeds `max_steps`.
inline std::optional<SegmentSteps> quantize(const Vec3& value, double step, int64_t max_steps) {
    SegmentSteps steps{};
    for (int k = 0; k < 3; ++k) {
        const double scaled = value[k] / step;
        if (!(std::fabs(scaled) <= double(max_steps))) return std::nullopt;
        steps[k] = std::llround(scaled);
    }
    return steps;
}

/// Greedy segment length: doubles the length while `fit_length(length)` succeeds, then bisects
/// between the last length that fit and the first that did not. Returns the fit of the longest
/// length found in at_least..max_length (1 <= at_least <= max_length), or nullopt when even
/// `at_least` frames do not fit. `fit_length(uint32_t)` returns std::optional<Fit>. A caller that
/// only wants a fit longer than one it has passes that length + 1, which skips the short probes.
template <class FitLength>
auto longest_greedy_fit(uint32_t max_length, FitLength fit_length, uint32_t at_least = 1) {
    auto best = fit_length(at_least);
    if (!best) return best;
    uint32_t good = at_least;
    uint32_t bad = 0;
    while (good < max_length) {
        const uint32_t next = std::min(2 * good, max_length);
        auto fit = fit_length(next);
        if (!fit) {
            bad = next;
            break;
        }
        best = fit;
        good = next;
    }
    while (bad > good + 1) {
        const uint32_t middle = good + (bad - good) / 2;
        auto fit = fit_length(middle);
        if (fit) {
            best = fit;
            good = middle;
        } else {
            bad = middle;
        }
    }
    return best;
}

/// Whether `within(j)` holds for every frame j in 1..length-1 of a candidate segment, whose last
/// frame the caller checked first (it gives the fit's end). The middle is visited first, then the
/// rest in order: most candidates the segment search tries are too long and fail at the end or
/// near the middle, so their check stops early; one that passes visits every frame either way.
template <class Within>
bool inner_frames_within(uint32_t length, Within within) {
    const uint32_t middle = length / 2;
    if (middle >= 1 && !within(middle)) return false;
    for (uint32_t j = 1; j < length; ++j)
        if (j != middle && !within(j)) return false;
    return true;
}

/// Least-squares sums of a segment's offsets r_j from its start (j = 1..L) against the basis of
/// CodecFormat.h: u = j / L and b = u (1 - u).
struct SegmentSums {
    double uu = 0, ub = 0, bb = 0;
    Vec3 ur{0, 0, 0}, br{0, 0, 0};
    Vec3 last{0, 0, 0};  ///< offset of the last frame added

    void add(double u, const Vec3& r) {
        const double b = u * (1 - u);
        uu += u * u;
        ub += u * b;
        bb += b * b;
        for (int k = 0; k < 3; ++k) {
            ur[k] += u * r[k];
            br[k] += b * r[k];
        }
        last = r;
    }
};

/// Tries the quantized end and bulge candidates of one segment and returns the one that
/// `check(end_steps, bulge_steps)` (-> std::optional<Fit>, Fit having `end_error`) accepts with
/// the smallest end error, which helps the next segment: from least squares with the start
/// fixed, from interpolating the last frame, and halfway between. Curved candidates also fit a
/// bulge; a one-frame segment has no middle and is fitted straight. (A candidate keeping the
/// previous segment's speed, whose end would cost nothing to code, was tried: no fewer bytes.)
template <class Check>
auto best_segment_candidate(const SegmentSums& sums, bool curved, double step, Check check) {
    curved = curved && sums.uu * sums.bb - sums.ub * sums.ub > 0;
    const double bulge_step = kBulgeStepRatio * step;
    decltype(check(SegmentSteps{}, SegmentSteps{})) best;
    Vec3 ends[3], bulges[3] = {};
    if (!curved) {
        ends[0] = scale(sums.ur, 1 / sums.uu);
        ends[1] = sums.last;
    } else {
        const double determinant = sums.uu * sums.bb - sums.ub * sums.ub;
        for (int k = 0; k < 3; ++k) {
            ends[0][k] = (sums.bb * sums.ur[k] - sums.ub * sums.br[k]) / determinant;
            bulges[0][k] = (sums.uu * sums.br[k] - sums.ub * sums.ur[k]) / determinant;
            ends[1][k] = sums.last[k];
            bulges[1][k] = (sums.br[k] - sums.ub * sums.last[k]) / sums.bb;
        }
    }
    ends[2] = scale(add(ends[0], ends[1]), 0.5);
    bulges[2] = scale(add(bulges[0], bulges[1]), 0.5);
    std::optional<std::pair<SegmentSteps, SegmentSteps>> tried[3];
    for (int c = 0; c < 3; ++c) {
        const auto end = quantize(ends[c], step, kMaxSegmentSteps);
        const auto bulge = quantize(bulges[c], bulge_step, kMaxSegmentSteps);
        if (!end || !bulge) continue;
        tried[c] = std::make_pair(*end, *bulge);
        if (std::find(tried, tried + c, tried[c]) != tried + c) continue;
        auto fit = check(*end, *bulge);
        if (fit && (!best || fit->end_error < best->end_error)) best = fit;
    }
    return best;
}

/// Writes tag, frame count and step exponent of a track.
inline void write_track_header(BitWriter& writer, uint8_t tag, uint32_t frame_count, int exponent) {
    writer.write_bits(tag, 8);
    write_sized_uint(writer, frame_count);
    writer.write_bits(static_cast<uint64_t>(exponent + kStepExponentBias), 8);
}

/// Writes the steps of a quantized start key.
inline void write_start_steps(BitWriter& writer, const SegmentSteps& steps) {
    for (int64_t value : steps) write_sized_uint(writer, zigzag_encode(value));
}

/// Largest power-of-two exponent e with 2^e <= bound * fraction. Throws std::invalid_argument
/// when `bound` is not positive and finite or e is outside the format's range.
inline int step_exponent_for(double bound, double fraction) {
    if (!std::isfinite(bound) || bound <= 0) {
        throw std::invalid_argument("codec: error bound must be positive and finite");
    }
    int exponent = 0;
    // frexp gives bound * fraction = m * 2^exponent with m in [0.5, 1).
    std::frexp(bound * fraction, &exponent);
    --exponent;
    if (exponent < kMinStepExponent || exponent > kMaxStepExponent) {
        throw std::invalid_argument("codec: error bound out of range");
    }
    return exponent;
}

/// Writes fit segment bodies in track order: the last bit, the length unless last, the bulge
/// when `curved` (format 2's curved segments), and the end step residuals against the
/// prediction, with adaptive Rice state mirrored by FitSegmentReader.
class FitSegmentWriter {
public:
    void write(BitWriter& writer, bool last, uint32_t length, const SegmentSteps& steps, bool curved,
               const SegmentSteps& bulge) {
        writer.write_bit(last);
        if (!last) lengths_.write_unsigned(writer, length - 1);
        const SegmentSteps used_bulge = curved ? bulge : SegmentSteps{};
        // Bulges of successive segments were found to be unrelated: coded as they are.
        if (curved) for (int k = 0; k < 3; ++k) bulges_[k].write_signed(writer, bulge[k]);
        const SegmentSteps predicted = predict_end_steps(previous_, length, used_bulge);
        for (int k = 0; k < 3; ++k) residuals_[k].write_signed(writer, steps[k] - predicted[k]);
        previous_ = {steps, used_bulge, length};
    }

    /// A raw segment restarts the prediction from zero.
    void reset_prediction() { previous_ = {}; }

private:
    AdaptiveRice lengths_{kLengthRiceInitialK};
    AdaptiveRice residuals_[3] = {AdaptiveRice(kResidualRiceInitialK),
                                  AdaptiveRice(kResidualRiceInitialK),
                                  AdaptiveRice(kResidualRiceInitialK)};
    AdaptiveRice bulges_[3] = {AdaptiveRice(kResidualRiceInitialK),
                               AdaptiveRice(kResidualRiceInitialK),
                               AdaptiveRice(kResidualRiceInitialK)};
    PreviousFit previous_;
};

}  // namespace mwb
