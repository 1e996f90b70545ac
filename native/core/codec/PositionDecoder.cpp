#include "codec/PositionDecoder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "codec/BitReader.h"
#include "codec/CodecError.h"
#include "codec/TrackReading.h"

namespace mwb {
namespace {

double read_finite_double(BitReader& reader) {
    const double value = reader.read_double();
    if (!std::isfinite(value)) throw CodecError("non-finite stored value");
    return value;
}

Vec3 read_start(BitReader& reader, double step_m) {
    if (!reader.read_bit()) return dequantize(read_start_steps(reader), step_m);
    Vec3 start{};
    for (double& value : start) value = read_finite_double(reader);
    return start;
}

}  // namespace

PositionTrackDecoder::PositionTrackDecoder(const uint8_t* data, size_t size) { parse(data, size); }

void PositionTrackDecoder::parse(const uint8_t* data, size_t size) {
    BitReader reader(data, size);
    const TrackHeader header = read_track_header(reader, kPositionTrackFormatV1, kPositionTrackFormatV2);
    frame_count_ = header.frame_count;
    step_m_ = header.step;
    const bool has_gravity = reader.read_bit();
    if (has_gravity) {
        for (double& value : quadratic_m_) {
            if (!reader.read_bit()) continue;
            value = reader.read_float();
            if (!std::isfinite(value)) throw CodecError("non-finite gravity term");
        }
    }
    const bool has_curves = header.format >= 2 && reader.read_bit();
    if (frame_count_ > 0) start_m_ = read_start(reader, start_key_step(header.format, step_m_));

    FitSegmentReader fit_reader;
    Vec3 position = start_m_;
    // Each segment covers at least one frame, so the loop ends after at most frame_count - 1
    // rounds, and each round consumes input, so a corrupted count cannot make it spin.
    for (uint32_t frame = 0; frame + 1 < frame_count_;) {
        Segment segment{frame, 1, reader.read_bit(), false, {}, {}, position};
        if (segment.raw) {
            for (double& value : segment.origin_m) value = read_finite_double(reader);
            fit_reader.reset_prediction();
        } else {
            segment.gravity = has_gravity && reader.read_bit();
            const bool curved = has_curves && reader.read_bit();
            const FitSegment fit = fit_reader.read(reader, frame_count_ - 1 - frame, curved);
            segment.length = fit.length;
            segment.steps = fit.steps;
            segment.bulge = fit.bulge;
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
    return position_on_segment(segment.origin_m, quadratic, segment.steps, segment.bulge, step_m_,
                               segment.length, frame_in_segment);
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
