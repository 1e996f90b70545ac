#pragma once
// Encoder-side pieces shared by the position and rotation encoders: segment search, quantization
// and the writing counterpart of TrackReading.h. Decoders never include this file.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>

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
/// length found in 1..max_length (max_length >= 1), or nullopt when even one frame does not fit.
/// `fit_length(uint32_t)` returns std::optional<Fit>.
template <class FitLength>
auto longest_greedy_fit(uint32_t max_length, FitLength fit_length) {
    auto best = fit_length(1);
    if (!best) return best;
    uint32_t good = 1;
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

/// Writes fit segment bodies in track order: the last bit, the length unless last, and the step
/// residuals against the prediction, with adaptive Rice state mirrored by FitSegmentReader.
class FitSegmentWriter {
public:
    void write(BitWriter& writer, bool last, uint32_t length, const SegmentSteps& steps) {
        writer.write_bit(last);
        if (!last) lengths_.write_unsigned(writer, length - 1);
        const SegmentSteps predicted = predict_segment_steps(previous_, previous_length_, length);
        for (int k = 0; k < 3; ++k) residuals_[k].write_signed(writer, steps[k] - predicted[k]);
        previous_ = steps;
        previous_length_ = length;
    }

    /// A raw segment restarts the prediction from zero.
    void reset_prediction() {
        previous_ = {};
        previous_length_ = 1;
    }

private:
    AdaptiveRice lengths_{kLengthRiceInitialK};
    AdaptiveRice residuals_[3] = {AdaptiveRice(kResidualRiceInitialK),
                                  AdaptiveRice(kResidualRiceInitialK),
                                  AdaptiveRice(kResidualRiceInitialK)};
    SegmentSteps previous_{};
    uint32_t previous_length_ = 1;
};

}  // namespace mwb
