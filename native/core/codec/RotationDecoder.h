#pragma once
// Reads orientation tracks written by encode_rotation_track. Depends on the format only
// (CodecFormat.h), never on the encoder.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/CodecFormat.h"
#include "common/Math.h"

namespace mwb {

/// A parsed orientation track. Construction reads and validates the whole buffer once and keeps a
/// table of segments (96 bytes each), so frames can then be decoded in any order. Decoded
/// quaternions are unit (w, x, y, z) and free of sign flips after frame 0 (consecutive frames
/// have a non-negative dot product unless the rotation itself jumps by more than pi).
/// Const member functions may be called from several threads at once.
class RotationTrackDecoder {
public:
    /// Parses `size` bytes at `data` (not kept). Throws CodecError when the buffer is truncated,
    /// corrupted, or not a rotation track of a known format version.
    RotationTrackDecoder(const uint8_t* data, size_t size);
    explicit RotationTrackDecoder(const std::vector<uint8_t>& bytes)
        : RotationTrackDecoder(bytes.data(), bytes.size()) {}

    uint32_t frame_count() const { return frame_count_; }
    /// Number of segments (raw escapes included) after the start key.
    size_t segment_count() const { return segments_.size(); }
    /// Quantization step of the rotation vectors and the start key, radians.
    double step_rad() const { return step_rad_; }

    /// Writes every frame to `out_wxyz`, flat (frame_count, 4) unit quaternions (w, x, y, z).
    void decode_all(double* out_wxyz) const;
    /// Orientation of one frame; bit-identical to the same frame of decode_all. Costs
    /// O(log segments + 1). Throws std::out_of_range when `frame` >= frame_count().
    Quat sample(uint32_t frame) const;

private:
    struct Segment {
        uint32_t first_frame;  // the segment covers first_frame + 1 .. first_frame + length
        uint32_t length;
        bool raw;
        SegmentSteps steps;
        SegmentSteps bulge;  // zero unless curved
        Quat origin;  // decoded orientation at first_frame, or the exact frame value if raw
    };

    void parse(const uint8_t* data, size_t size);
    Quat evaluate(const Segment& segment, uint32_t frame_in_segment) const;

    uint32_t frame_count_ = 0;
    double step_rad_ = 0;
    Quat start_{1, 0, 0, 0};
    std::vector<Segment> segments_;
};

}  // namespace mwb
