#pragma once
// Reads position tracks written by encode_position_track. Depends on the format only
// (CodecFormat.h), never on the encoder.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/CodecFormat.h"
#include "common/Math.h"

namespace mwb {

/// A parsed position track. Construction reads and validates the whole buffer once and keeps a
/// table of segments (88 bytes each), so frames can then be decoded in any order. Const
/// member functions may be called from several threads at once.
class PositionTrackDecoder {
public:
    /// Parses `size` bytes at `data` (not kept). Throws CodecError when the buffer is truncated,
    /// corrupted, or not a position track of a known format version.
    PositionTrackDecoder(const uint8_t* data, size_t size);
    explicit PositionTrackDecoder(const std::vector<uint8_t>& bytes)
        : PositionTrackDecoder(bytes.data(), bytes.size()) {}

    uint32_t frame_count() const { return frame_count_; }
    /// Number of spline segments (raw escapes included) after the start key.
    size_t segment_count() const { return segments_.size(); }
    /// Quantization step of the linear terms and the start key, metres.
    double step_m() const { return step_m_; }

    /// Writes every frame to `out_xyz_m`, flat (frame_count, 3), metres.
    void decode_all(double* out_xyz_m) const;
    /// Position of one frame, metres; bit-identical to the same frame of decode_all. Costs
    /// O(log segments + 1). Throws std::out_of_range when `frame` >= frame_count().
    Vec3 sample(uint32_t frame) const;

private:
    struct Segment {
        uint32_t first_frame;  // the segment covers first_frame + 1 .. first_frame + length
        uint32_t length;
        bool raw;
        bool gravity;
        SegmentSteps steps;
        SegmentSteps bulge;  // zero unless curved
        Vec3 origin_m;  // decoded position at first_frame, or the exact frame value if raw
    };

    void parse(const uint8_t* data, size_t size);
    Vec3 evaluate(const Segment& segment, uint32_t frame_in_segment) const;

    uint32_t frame_count_ = 0;
    double step_m_ = 0;
    Vec3 quadratic_m_{0, 0, 0};
    Vec3 start_m_{0, 0, 0};
    std::vector<Segment> segments_;
};

}  // namespace mwb
