#include "codec/RotationDecoder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "codec/BitReader.h"
#include "codec/CodecError.h"
#include "codec/TrackReading.h"

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

Quat read_start(BitReader& reader, double step_rad) {
    if (reader.read_bit()) return read_unit_quaternion(reader);
    return rotation_from_steps(read_start_steps(reader), step_rad);
}

}  // namespace

RotationTrackDecoder::RotationTrackDecoder(const uint8_t* data, size_t size) { parse(data, size); }

void RotationTrackDecoder::parse(const uint8_t* data, size_t size) {
    BitReader reader(data, size);
    const TrackHeader header = read_track_header(reader, kRotationTrackFormatV1, kRotationTrackFormatV2);
    frame_count_ = header.frame_count;
    step_rad_ = header.step;
    const bool has_curves = header.format >= 2 && reader.read_bit();
    if (frame_count_ > 0) start_ = read_start(reader, start_key_step(header.format, step_rad_));

    FitSegmentReader fit_reader;
    Quat rotation = start_;
    // Each segment covers at least one frame, so the loop ends after at most frame_count - 1
    // rounds, and each round consumes input, so a corrupted count cannot make it spin.
    for (uint32_t frame = 0; frame + 1 < frame_count_;) {
        Segment segment{frame, 1, reader.read_bit(), {}, {}, rotation};
        if (segment.raw) {
            segment.origin = read_unit_quaternion(reader);
            fit_reader.reset_prediction();
        } else {
            const bool curved = has_curves && reader.read_bit();
            const FitSegment fit = fit_reader.read(reader, frame_count_ - 1 - frame, curved);
            segment.length = fit.length;
            segment.steps = fit.steps;
            segment.bulge = fit.bulge;
        }
        segments_.push_back(segment);
        rotation = evaluate(segment, segment.length);
        frame += segment.length;
    }
    reader.require_end();
}

Quat RotationTrackDecoder::evaluate(const Segment& segment, uint32_t frame_in_segment) const {
    if (segment.raw) return segment.origin;
    return rotation_on_segment(segment.origin, segment.steps, segment.bulge, step_rad_, segment.length,
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
