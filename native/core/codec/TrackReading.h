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
    uint32_t frame_count = 0;
    double step = 0;  ///< quantization step, metres or radians
};

/// Reads and validates tag, frame count and step exponent. Throws CodecError.
inline TrackHeader read_track_header(BitReader& reader, uint8_t expected_tag) {
    if (reader.read_bits(8) != expected_tag) {
        throw CodecError("not a track of the expected kind and a supported format version");
    }
    const uint64_t count = read_sized_uint(reader);
    if (count > std::numeric_limits<uint32_t>::max()) throw CodecError("frame count too large");
    const int exponent = static_cast<int>(reader.read_bits(8)) - kStepExponentBias;
    if (exponent < kMinStepExponent || exponent > kMaxStepExponent) {
        throw CodecError("quantization step out of range");
    }
    return {static_cast<uint32_t>(count), std::ldexp(1.0, exponent)};
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

/// Length and steps of one fit segment.
struct FitSegment {
    uint32_t length = 0;
    SegmentSteps steps{};
};

/// Reads fit segment bodies in track order, mirroring the encoder's adaptive Rice state and
/// step prediction.
class FitSegmentReader {
public:
    /// Reads the last bit, the length and the step residuals of a segment that may cover at most
    /// `remaining_frames` frames. Throws CodecError on truncated or inconsistent data.
    FitSegment read(BitReader& reader, uint32_t remaining_frames) {
        FitSegment segment;
        segment.length = reader.read_bit() ? remaining_frames : read_length(reader, remaining_frames);
        if (segment.length > kMaxSegmentFrames) throw CodecError("segment too long");
        const SegmentSteps predicted = predict_segment_steps(previous_, previous_length_, segment.length);
        for (int k = 0; k < 3; ++k) {
            const int64_t residual = residuals_[k].read_signed(reader);
            // Bounding the residual first keeps the sum from overflowing.
            if (residual > 2 * kMaxSegmentSteps || residual < -2 * kMaxSegmentSteps) {
                throw CodecError("segment steps out of range");
            }
            segment.steps[k] = predicted[k] + residual;
            if (segment.steps[k] > kMaxSegmentSteps || segment.steps[k] < -kMaxSegmentSteps) {
                throw CodecError("segment steps out of range");
            }
        }
        previous_ = segment.steps;
        previous_length_ = segment.length;
        return segment;
    }

    /// A raw segment restarts the prediction from zero.
    void reset_prediction() {
        previous_ = {};
        previous_length_ = 1;
    }

private:
    uint32_t read_length(BitReader& reader, uint32_t remaining_frames) {
        const uint64_t length_minus_one = lengths_.read_unsigned(reader);
        if (length_minus_one >= remaining_frames) throw CodecError("segment runs past the track");
        return static_cast<uint32_t>(length_minus_one) + 1;
    }

    AdaptiveRice lengths_{kLengthRiceInitialK};
    AdaptiveRice residuals_[3] = {AdaptiveRice(kResidualRiceInitialK),
                                  AdaptiveRice(kResidualRiceInitialK),
                                  AdaptiveRice(kResidualRiceInitialK)};
    SegmentSteps previous_{};
    uint32_t previous_length_ = 1;
};

}  // namespace mwb
