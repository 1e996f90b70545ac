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

PolylineLayout polyline_layout(const StoredWorld& world, double rate_hz) {
    PolylineLayout layout;
    const uint32_t frames = world.frame_count;
    layout.stride = std::max<uint32_t>(1, static_cast<uint32_t>(std::lround(world.record_hz / rate_hz)));
    layout.points = frames == 0 ? 0 : (frames - 1 + layout.stride - 1) / layout.stride + 1;
    return layout;
}

std::vector<uint16_t> track_polyline(const StoredTrack& track, uint32_t world_frames, const PolylineLayout& layout) {
    std::vector<uint16_t> block(quantized::block_words(layout.points));
    if (!track.present) {
        quantized::encode_absent(layout.points, block.data());
        return block;
    }
    // One track at a time: a track's frames are about 115 kB, where the whole world's were
    // 1.3 MB (the staircase's 11 bodies over 4,800 frames at 120 Hz) allocated per world.
    std::vector<double> positions(size_t{world_frames} * 3);
    decode_track<PositionTrackDecoder>(track.position, track, world_frames, 3, positions.data());
    quantized::encode(
        layout.points,
        [&](uint32_t p, int axis) {
            const size_t frame = std::min<size_t>(size_t{p} * layout.stride, world_frames - 1);
            return positions[frame * 3 + static_cast<size_t>(axis)];
        },
        block.data());
    return block;
}

void derive_polyline(StoredWorld& world, double rate_hz, const std::vector<std::vector<uint16_t>>& known) {
    const PolylineLayout layout = polyline_layout(world, rate_hz);
    const size_t words = quantized::block_words(layout.points);
    std::vector<uint16_t> polyline(world.tracks.size() * words);
    for (size_t t = 0; t < world.tracks.size(); ++t) {
        const bool given = t < known.size() && known[t].size() == words;
        const std::vector<uint16_t> derived =
            given ? std::vector<uint16_t>() : track_polyline(world.tracks[t], world.frame_count, layout);
        const std::vector<uint16_t>& block = given ? known[t] : derived;
        std::copy(block.begin(), block.end(), polyline.begin() + static_cast<std::ptrdiff_t>(t * words));
    }
    world.polyline = std::move(polyline);
    world.polyline_points = layout.points;
    world.polyline_stride = layout.stride;
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

std::vector<std::vector<Quat>> rotations_at_path_points(const StoredWorld& world, const std::vector<uint32_t>& bodies) {
    std::vector<uint32_t> frames;
    for (uint32_t k = 0; k < world.polyline_points; ++k)
        frames.push_back(static_cast<uint32_t>(
            std::min<uint64_t>(uint64_t{k} * world.polyline_stride, world.frame_count - 1)));
    std::vector<std::vector<Quat>> out(world.tracks.size());
    for (uint32_t body : bodies)
        if (body < world.tracks.size() && world.tracks[body].present) out[body] = decode_rotations(world, body, frames);
    return out;
}

}  // namespace mwb
