#pragma once
// Decompresses stored worlds: all frames of every stored body, or one body at one frame without
// touching the rest of the world. Throws CodecError for damaged tracks.
#include <cstdint>
#include <vector>

#include "library/WorldRecord.h"
#include "scene/Scene.h"

namespace mwb {

/// (bodies, frames, 3) object origins, metres; bodies = max(body_count, tracks). Bodies the world
/// does not have (absent tracks, or beyond its tracks when the scene grew later) are NaN.
std::vector<double> decode_world_positions(const StoredWorld& world, size_t body_count = 0);
/// (bodies, frames, 4) unit quaternions (w, x, y, z), NaN for bodies the world does not have.
std::vector<double> decode_world_orientations(const StoredWorld& world, size_t body_count = 0);
/// How a world's polyline samples its frames at about `rate_hz`: every stride-th frame (a whole
/// divisor of the record rate) and always the last, `points` in all.
struct PolylineLayout {
    uint32_t stride = 1, points = 0;
};
PolylineLayout polyline_layout(const StoredWorld& world, double rate_hz);
/// One track's block of a polyline (quantized::block_words(layout.points) words) for a world of
/// `world_frames` frames: NaN points for an absent track.
std::vector<uint16_t> track_polyline(const StoredTrack& track, uint32_t world_frames, const PolylineLayout& layout);
/// Fills world.polyline with every track sampled as polyline_layout(world, rate_hz) says. `known`:
/// per track, its block when derived already (in parallel, or unchanged from a parent world of the
/// same layout), empty otherwise.
void derive_polyline(StoredWorld& world, double rate_hz, const std::vector<std::vector<uint16_t>>& known = {});
/// One track at one frame (frame counted from the world's first_frame); CodecError if absent.
Transform decode_pose(const StoredWorld& world, size_t track, uint32_t frame);
/// One track's orientations at `frames` (each as in decode_pose, and bit-identical to its), the
/// track parsed once: sampling a path's points through decode_pose parses it once a point.
std::vector<Quat> decode_rotations(const StoredWorld& world, size_t track, const std::vector<uint32_t>& frames);
/// Per track, the rotations at the world's polyline points (the frames its paths sample) for the
/// tracks `bodies` it has; empty for the others. Pose parts of a goal read these.
std::vector<std::vector<Quat>> rotations_at_path_points(const StoredWorld& world, const std::vector<uint32_t>& bodies);

}  // namespace mwb
