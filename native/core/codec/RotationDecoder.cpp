#include "codec/RotationDecoder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "codec/BitReader.h"
#include "codec/CodecError.h"
#include "codec/RiceCode.h"

namespace mwb {
namespace {

// Raw quaternions are stored normalized; a larger deviation means corruption.
constexpr double kRawNormTolerance = 1e-9;

Quat read_unit_quaternion(BitReader& reader) {
    Quat q{};
    for (double& value : q) value = reader.read_double();
    const double squared = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    // Also rejects NaN and infinities, for which the comparison is false.
    if (!(std::fabs(squared - 1) <= kRawNormTolerance)) throw CodecError("raw rotation not unit");
    return q;
}

uint32_t read_frame_count(BitReader& reader) {
    const uint64_t count = read_sized_uint(reader);
    if (count > std::numeric_limits<uint32_t>::max()) throw CodecError("frame count too large");
    return static_cast<uint32_t>(count);
}

double read_step(BitReader& reader) {
    const int exponent = static_cast<int>(reader.read_bits(8)) - kStepExponentBias;
    if (exponent < kMinStepExponent || exponent > kMaxStepExponent) {
        throw CodecError("quantization step out of range");
    }
    return std::ldexp(1.0, exponent);
}

Quat read_start(BitReader& reader, double step_rad) {
    if (reader.read_bit()) return read_unit_quaternion(reader);
    SegmentSteps steps{};
    for (int64_t& value : steps) {
        value = zigzag_decode(read_sized_uint(reader));
        if (value > kMaxStartSteps || value < -kMaxStartSteps) {
            throw CodecError("start rotation out of range");
        }
    }
    return rotation_from_steps(steps, step_rad);
}

}  // namespace

RotationTrackDecoder::RotationTrackDecoder(const uint8_t* data, size_t size) { parse(data, size); }

void RotationTrackDecoder::parse(const uint8_t* data, size_t size) {
    BitReader reader(data, size);
    if (reader.read_bits(8) != kRotationTrackFormatV1) {
        throw CodecError("not a rotation track of a supported format version");
    }
    frame_count_ = read_frame_count(reader);
    step_rad_ = read_step(reader);
    if (frame_count_ > 0) start_ = read_start(reader, step_rad_);

    AdaptiveRice lengths(kLengthRiceInitialK);
    AdaptiveRice residuals[3] = {AdaptiveRice(kResidualRiceInitialK),
                                 AdaptiveRice(kResidualRiceInitialK),
                                 AdaptiveRice(kResidualRiceInitialK)};
    SegmentSteps previous{};
    uint32_t previous_length = 1;
    Quat rotation = start_;
    // Each segment covers at least one frame, so the loop ends after at most frame_count - 1
    // rounds, and each round consumes input, so a corrupted count cannot make it spin.
    for (uint32_t frame = 0; frame + 1 < frame_count_;) {
        const uint32_t remaining = frame_count_ - 1 - frame;
        Segment segment{frame, 1, reader.read_bit(), {}, rotation};
        if (segment.raw) {
            segment.origin = read_unit_quaternion(reader);
            previous = {};
            previous_length = 1;
        } else {
            if (reader.read_bit()) {
                segment.length = remaining;
            } else {
                const uint64_t length_minus_one = lengths.read_unsigned(reader);
                if (length_minus_one >= remaining) throw CodecError("segment runs past the track");
                segment.length = static_cast<uint32_t>(length_minus_one) + 1;
            }
            if (segment.length > kMaxSegmentFrames) throw CodecError("segment too long");
            const SegmentSteps predicted =
                predict_segment_steps(previous, previous_length, segment.length);
            for (int k = 0; k < 3; ++k) {
                const int64_t residual = residuals[k].read_signed(reader);
                // Bounding the residual first keeps the sum from overflowing.
                if (residual > 2 * kMaxSegmentSteps || residual < -2 * kMaxSegmentSteps) {
                    throw CodecError("segment steps out of range");
                }
                segment.steps[k] = predicted[k] + residual;
                if (segment.steps[k] > kMaxSegmentSteps || segment.steps[k] < -kMaxSegmentSteps) {
                    throw CodecError("segment steps out of range");
                }
            }
            previous = segment.steps;
            previous_length = segment.length;
        }
        segments_.push_back(segment);
        rotation = evaluate(segment, segment.length);
        frame += segment.length;
    }
    reader.require_end();
}

Quat RotationTrackDecoder::evaluate(const Segment& segment, uint32_t frame_in_segment) const {
    if (segment.raw) return segment.origin;
    return rotation_on_segment(segment.origin, segment.steps, step_rad_, segment.length,
                               frame_in_segment);
}

void RotationTrackDecoder::decode_all(double* out_wxyz) const {
    if (frame_count_ == 0) return;
    std::copy(start_.begin(), start_.end(), out_wxyz);
    for (const Segment& segment : segments_) {
        for (uint32_t j = 1; j <= segment.length; ++j) {
            const Quat q = evaluate(segment, j);
            std::copy(q.begin(), q.end(), out_wxyz + 4 * (size_t{segment.first_frame} + j));
        }
    }
}

Quat RotationTrackDecoder::sample(uint32_t frame) const {
    if (frame >= frame_count_) throw std::out_of_range("RotationTrackDecoder::sample: frame");
    if (frame == 0) return start_;
    // The first segment whose covered range ends at or after `frame`.
    const auto it = std::lower_bound(
        segments_.begin(), segments_.end(), frame,
        [](const Segment& s, uint32_t f) { return s.first_frame + s.length < f; });
    return evaluate(*it, frame - it->first_frame);
}

}  // namespace mwb
