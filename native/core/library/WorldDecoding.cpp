#include "library/WorldDecoding.h"

#include <algorithm>
#include <cmath>

#include "codec/CodecError.h"
#include "codec/PositionDecoder.h"
#include "codec/RotationDecoder.h"

namespace mwb {
namespace {

template <typename Decoder>
Decoder checked_decoder(const std::vector<uint8_t>& bytes, uint32_t frame_count, uint32_t body) {
    Decoder decoder(bytes.data(), bytes.size());
    if (decoder.frame_count() != frame_count)
        throw CodecError("track of body " + std::to_string(body) + " has " + std::to_string(decoder.frame_count()) +
                         " frames, its world " + std::to_string(frame_count));
    return decoder;
}

}  // namespace

std::vector<double> decode_world_positions(const StoredWorld& world) {
    const size_t frames = world.frame_count;
    std::vector<double> out(world.tracks.size() * frames * 3);
    for (size_t t = 0; t < world.tracks.size(); ++t)
        checked_decoder<PositionTrackDecoder>(world.tracks[t].position, world.frame_count, world.tracks[t].body)
            .decode_all(&out[t * frames * 3]);
    return out;
}

std::vector<double> decode_world_orientations(const StoredWorld& world) {
    const size_t frames = world.frame_count;
    std::vector<double> out(world.tracks.size() * frames * 4);
    for (size_t t = 0; t < world.tracks.size(); ++t)
        checked_decoder<RotationTrackDecoder>(world.tracks[t].rotation, world.frame_count, world.tracks[t].body)
            .decode_all(&out[t * frames * 4]);
    return out;
}

void derive_polyline(StoredWorld& world, double rate_hz) {
    const uint32_t frames = world.frame_count;
    const uint32_t stride = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(world.record_hz / rate_hz)));
    const uint32_t points = frames == 0 ? 0 : (frames - 1 + stride - 1) / stride + 1;
    const std::vector<double> positions = decode_world_positions(world);
    world.polyline.assign(world.tracks.size() * points * 3, 0.0f);
    for (size_t t = 0; t < world.tracks.size(); ++t) {
        for (uint32_t p = 0; p < points; ++p) {
            const size_t frame = std::min<size_t>(size_t{p} * stride, frames - 1);
            for (int k = 0; k < 3; ++k)
                world.polyline[(t * points + p) * 3 + k] = static_cast<float>(positions[(t * frames + frame) * 3 + k]);
        }
    }
    world.polyline_points = points;
    world.polyline_stride = stride;
}

Transform decode_pose(const StoredWorld& world, size_t track, uint32_t frame) {
    const StoredTrack& t = world.tracks.at(track);
    if (frame >= world.frame_count) throw CodecError("frame " + std::to_string(frame) + " beyond the world's " +
                                                     std::to_string(world.frame_count));
    return {PositionTrackDecoder(t.position.data(), t.position.size()).sample(frame),
            RotationTrackDecoder(t.rotation.data(), t.rotation.size()).sample(frame)};
}

}  // namespace mwb
