#include "codec/PositionDecoder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "codec/BitReader.h"
#include "codec/CodecError.h"
#include "codec/RiceCode.h"

namespace mwb {
namespace {

double read_finite_double(BitReader& reader) {
    const double value = reader.read_double();
    if (!std::isfinite(value)) throw CodecError("non-finite stored value");
    return value;
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

Vec3 read_start(BitReader& reader, double step_m) {
    Vec3 start{};
    const bool raw = reader.read_bit();
    SegmentSteps steps{};
    for (int k = 0; k < 3; ++k) {
        if (raw) {
            start[k] = read_finite_double(reader);
            continue;
        }
        steps[k] = zigzag_decode(read_sized_uint(reader));
        if (steps[k] > kMaxStartSteps || steps[k] < -kMaxStartSteps) {
            throw CodecError("start position out of range");
        }
    }
    return raw ? start : dequantize(steps, step_m);
}

}  // namespace

PositionTrackDecoder::PositionTrackDecoder(const uint8_t* data, size_t size) { parse(data, size); }

void PositionTrackDecoder::parse(const uint8_t* data, size_t size) {
    BitReader reader(data, size);
    if (reader.read_bits(8) != kPositionTrackFormatV1) {
        throw CodecError("not a position track of a supported format version");
    }
    frame_count_ = read_frame_count(reader);
    step_m_ = read_step(reader);
    const bool has_gravity = reader.read_bit();
    if (has_gravity) {
        for (double& value : quadratic_m_) {
            if (!reader.read_bit()) continue;
            value = reader.read_float();
            if (!std::isfinite(value)) throw CodecError("non-finite gravity term");
        }
    }
    if (frame_count_ > 0) start_m_ = read_start(reader, step_m_);

    AdaptiveRice lengths(kLengthRiceInitialK);
    AdaptiveRice residuals[3] = {AdaptiveRice(kResidualRiceInitialK),
                                 AdaptiveRice(kResidualRiceInitialK),
                                 AdaptiveRice(kResidualRiceInitialK)};
    SegmentSteps previous{};
    uint32_t previous_length = 1;
    Vec3 position = start_m_;
    // Each segment covers at least one frame, so the loop ends after at most frame_count - 1
    // rounds, and each round consumes input, so a corrupted count cannot make it spin.
    for (uint32_t frame = 0; frame + 1 < frame_count_;) {
        const uint32_t remaining = frame_count_ - 1 - frame;
        Segment segment{frame, 1, reader.read_bit(), false, {}, position};
        if (segment.raw) {
            for (double& value : segment.origin_m) value = read_finite_double(reader);
            previous = {};
            previous_length = 1;
        } else {
            segment.gravity = has_gravity && reader.read_bit();
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
        position = evaluate(segment, segment.length);
        frame += segment.length;
    }
    reader.require_end();
}

Vec3 PositionTrackDecoder::evaluate(const Segment& segment, uint32_t frame_in_segment) const {
    if (segment.raw) return segment.origin_m;
    const Vec3 quadratic = segment.gravity ? quadratic_m_ : Vec3{0, 0, 0};
    return position_on_segment(segment.origin_m, quadratic, segment.steps, step_m_, segment.length,
                               frame_in_segment);
}

void PositionTrackDecoder::decode_all(double* out_xyz_m) const {
    if (frame_count_ == 0) return;
    std::copy(start_m_.begin(), start_m_.end(), out_xyz_m);
    for (const Segment& segment : segments_) {
        for (uint32_t j = 1; j <= segment.length; ++j) {
            const Vec3 p = evaluate(segment, j);
            std::copy(p.begin(), p.end(), out_xyz_m + 3 * (size_t{segment.first_frame} + j));
        }
    }
}

Vec3 PositionTrackDecoder::sample(uint32_t frame) const {
    if (frame >= frame_count_) throw std::out_of_range("PositionTrackDecoder::sample: frame");
    if (frame == 0) return start_m_;
    // The first segment whose covered range ends at or after `frame`.
    const auto it = std::lower_bound(
        segments_.begin(), segments_.end(), frame,
        [](const Segment& s, uint32_t f) { return s.first_frame + s.length < f; });
    return evaluate(*it, frame - it->first_frame);
}

}  // namespace mwb
