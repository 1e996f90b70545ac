#include "library/WorldDecoding.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "codec/CodecError.h"
#include "codec/PositionDecoder.h"
#include "codec/RotationDecoder.h"
#include "common/QuantizedPolyline.h"

namespace mwb {
namespace {

// Decodes one track into `out` (world frames × width): a track of the world's own length must
// match it; an inherited one is cut or held at its last frame to the world's length.
template <typename Decoder>
void decode_track(const std::vector<uint8_t>& bytes, const StoredTrack& track, uint32_t world_frames, int width,
                  double* out) {
    const Decoder decoder(bytes.data(), bytes.size());
    const uint32_t frames = decoder.frame_count();
    if (frames == world_frames) {
        decoder.decode_all(out);
        return;
    }
    if (!track.inherited || frames == 0)
        throw CodecError("track of body " + std::to_string(track.body) + " has " + std::to_string(frames) +
                         " frames, its world " + std::to_string(world_frames));
    std::vector<double> own(size_t{frames} * width);
    decoder.decode_all(own.data());
    for (uint32_t f = 0; f < world_frames; ++f) {
        const size_t from = std::min(f, frames - 1);
        std::copy(&own[from * width], &own[from * width] + width, out + size_t{f} * width);
    }
}

// Every present track's `blob` decoded into (bodies, frames, width), NaN for bodies the world lacks.
template <typename Decoder>
std::vector<double> decode_all(const StoredWorld& world, size_t body_count, int width,
                               std::vector<uint8_t> StoredTrack::*blob) {
    body_count = std::max(body_count, world.tracks.size());
    const size_t frames = world.frame_count;
    std::vector<double> out(body_count * frames * width, std::numeric_limits<double>::quiet_NaN());
    for (size_t t = 0; t < world.tracks.size(); ++t)
        if (world.tracks[t].present)
            decode_track<Decoder>(world.tracks[t].*blob, world.tracks[t], world.frame_count, width, &out[t * frames * width]);
    return out;
}

const StoredTrack& present_track(const StoredWorld& world, size_t track) {
    const StoredTrack& t = world.tracks.at(track);
    if (!t.present) throw CodecError("body " + std::to_string(t.body) + " is not in world " + std::to_string(world.world_index));
    return t;
}

void check_frame(const StoredWorld& world, uint32_t frame) {
    if (frame >= world.frame_count)
        throw CodecError("frame " + std::to_string(frame) + " beyond the world's " + std::to_string(world.frame_count));
}

}  // namespace

std::vector<double> decode_world_positions(const StoredWorld& world, size_t body_count) {
    return decode_all<PositionTrackDecoder>(world, body_count, 3, &StoredTrack::position);
}

std::vector<double> decode_world_orientations(const StoredWorld& world, size_t body_count) {
    return decode_all<RotationTrackDecoder>(world, body_count, 4, &StoredTrack::rotation);
}

void derive_polyline(StoredWorld& world, double rate_hz) {
    const uint32_t frames = world.frame_count;
    const uint32_t stride = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(world.record_hz / rate_hz)));
    const uint32_t points = frames == 0 ? 0 : (frames - 1 + stride - 1) / stride + 1;
    const std::vector<double> positions = decode_world_positions(world);
    const size_t words = quantized::block_words(points);
    world.polyline.assign(world.tracks.size() * words, 0);
    for (size_t t = 0; t < world.tracks.size(); ++t) {
        uint16_t* block = world.polyline.data() + t * words;
        if (!world.tracks[t].present) {
            quantized::encode_absent(points, block);
            continue;
        }
        quantized::encode(
            points,
            [&](uint32_t p, int axis) {
                const size_t frame = std::min<size_t>(size_t{p} * stride, frames - 1);
                return positions[(t * frames + frame) * 3 + static_cast<size_t>(axis)];
            },
            block);
    }
    world.polyline_points = points;
    world.polyline_stride = stride;
}

Transform decode_pose(const StoredWorld& world, size_t track, uint32_t frame) {
    const StoredTrack& t = present_track(world, track);
    check_frame(world, frame);
    const PositionTrackDecoder position(t.position.data(), t.position.size());
    const RotationTrackDecoder rotation(t.rotation.data(), t.rotation.size());
    if (position.frame_count() == 0 || rotation.frame_count() == 0) throw CodecError("empty track");
    // Inherited tracks hold their last frame past their end.
    return {position.sample(std::min(frame, position.frame_count() - 1)),
            rotation.sample(std::min(frame, rotation.frame_count() - 1))};
}

std::vector<Quat> decode_rotations(const StoredWorld& world, size_t track, const std::vector<uint32_t>& frames) {
    const StoredTrack& t = present_track(world, track);
    const RotationTrackDecoder rotation(t.rotation.data(), t.rotation.size());
    if (rotation.frame_count() == 0) throw CodecError("empty track");
    std::vector<Quat> out;
    out.reserve(frames.size());
    for (uint32_t frame : frames) {
        check_frame(world, frame);
        out.push_back(rotation.sample(std::min(frame, rotation.frame_count() - 1)));
    }
    return out;
}

}  // namespace mwb
