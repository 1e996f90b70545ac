#pragma once
// Decompresses stored worlds: all frames of every stored body, or one body at one frame without
// touching the rest of the world. Throws CodecError for damaged tracks.
#include <vector>

#include "library/WorldRecord.h"
#include "scene/Scene.h"

namespace mwb {

/// (tracks, frames, 3) object origins, metres.
std::vector<double> decode_world_positions(const StoredWorld& world);
/// (tracks, frames, 4) unit quaternions (w, x, y, z).
std::vector<double> decode_world_orientations(const StoredWorld& world);
/// Fills world.polyline with every track sampled at about `rate_hz` (a whole divisor of the
/// record rate; the last frame is always included).
void derive_polyline(StoredWorld& world, double rate_hz);
/// One track at one frame (frame counted from the world's first_frame).
Transform decode_pose(const StoredWorld& world, size_t track, uint32_t frame);

}  // namespace mwb
