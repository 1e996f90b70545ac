#pragma once
// Turns a simulated world into a record payload: motion compressed under the codec bounds,
// metrics computed from the full-rate motion, checkpoints deflated.
#include <vector>

#include "codec/CodecFormat.h"
#include "library/WorldRecord.h"

namespace mwb {

/// Record payload of an Ok world. `gravity` is the scene's (the codec's one-bit quadratic term).
std::vector<uint8_t> encode_world_record(const WorldResult& world, const CodecBounds& bounds, const Vec3& gravity);
std::vector<uint8_t> encode_rejection_record(const WorldResult& world);

}  // namespace mwb
