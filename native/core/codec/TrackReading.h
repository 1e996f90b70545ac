#pragma once
// Decoder-side pieces shared by the position and rotation decoders: the common track header and
// the body of a fit segment (see CodecFormat.h for the layout).
#include <cmath>
#include <cstdint>
#include <limits>

#include "codec/BitReader.h"
#include "codec/CodecError.h"
#include "codec/CodecFormat.h"
#include "codec/RiceCode.h"

namespace mwb {

struct TrackHeader {
    int format = 1;  ///< 1 or 2 (format 2 may have curved segments)
    uint32_t frame_count = 0;
    double step = 0;  ///< quantization step, metres or radians
};

/// Reads and validates tag (format 1 or 2 of the expected kind), frame count and step exponent.
/// Throws CodecError.
inline TrackHeader read_track_header(BitReader& reader, uint8_t tag_v1, uint8_t tag_v2) {
    const uint64_t tag = reader.read_bits(8);
    if (tag != tag_v1 && tag != tag_v2) {
        throw CodecError("not a track of the expected kind and a supported format version");
    }
    const uint64_t count = read_sized_uint(reader);
    if (count > std::numeric_limits<uint32_t>::max()) throw CodecError("frame count too large");
    const int exponent = static_cast<int>(reader.read_bits(8)) - kStepExponentBias;
    if (exponent < kMinStepExponent || exponent > kMaxStepExponent) {
        throw CodecError("quantization step out of range");
    }
    return {tag == tag_v2 ? 2 : 1, static_cast<uint32_t>(count), std::ldexp(1.0, exponent)};
}

/// Reads the steps of a quantized start key. Throws CodecError.
inline SegmentSteps read_start_steps(BitReader& reader) {
    SegmentSteps steps{};
    for (int64_t& value : steps) {
        value = zigzag_decode(read_sized_uint(reader));
        if (value > kMaxStartSteps || value < -kMaxStartSteps) throw CodecError("start key out of range");
    }
    return steps;
}

/// Length, end steps and bulge (zero unless curved) of one fit segment.
struct FitSegment {
    uint32_t length = 0;
    SegmentSteps steps{};
    SegmentSteps bulge{};
};

/// Reads fit segment bodies in track order, mirroring the encoder's adaptive Rice state and
/// step prediction.
class FitSegmentReader {
public:
    /// Reads the last bit, the length, the bulge when `curved` and the end step
    /// residuals of a segment that may cover at most `remaining_frames` frames. Throws CodecError
    /// on truncated or inconsistent data.
    FitSegment read(BitReader& reader, uint32_t remaining_frames, bool curved) {
        FitSegment segment;
        segment.length = reader.read_bit() ? remaining_frames : read_length(reader, remaining_frames);
        if (segment.length > kMaxSegmentFrames) throw CodecError("segment too long");
        if (curved) segment.bulge = read_steps(reader, bulges_, SegmentSteps{});
        segment.steps = read_steps(reader, residuals_, predict_end_steps(previous_, segment.length, segment.bulge));
        previous_ = {segment.steps, segment.bulge, segment.length};
        return segment;
    }

    /// A raw segment restarts the prediction from zero.
    void reset_prediction() { previous_ = {}; }

private:
    static SegmentSteps read_steps(BitReader& reader, AdaptiveRice* coders, const SegmentSteps& predicted) {
        SegmentSteps steps{};
        for (int k = 0; k < 3; ++k) {
            const int64_t residual = coders[k].read_signed(reader);
            // Bounding the residual first keeps the sum from overflowing.
            if (residual > 2 * kMaxSegmentSteps || residual < -2 * kMaxSegmentSteps) {
                throw CodecError("segment steps out of range");
            }
            steps[k] = predicted[k] + residual;
            if (steps[k] > kMaxSegmentSteps || steps[k] < -kMaxSegmentSteps) {
                throw CodecError("segment steps out of range");
            }
        }
        return steps;
    }

    uint32_t read_length(BitReader& reader, uint32_t remaining_frames) {
        const uint64_t length_minus_one = lengths_.read_unsigned(reader);
        if (length_minus_one >= remaining_frames) throw CodecError("segment runs past the track");
        return static_cast<uint32_t>(length_minus_one) + 1;
    }

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
