#pragma once
// Checkpoints are stored deflated (zlib): full-precision states of every body every 0.5 s would
// otherwise outweigh the compressed motion.
#include <vector>

#include "library/ByteIO.h"
#include "sim/WorldResult.h"

namespace mwb {

void write_checkpoints(ByteWriter& out, const std::vector<Checkpoint>& checkpoints, uint32_t body_count,
                       uint32_t joint_count);
/// `record_version`: the world record's version, which decides the checkpoint layout.
std::vector<Checkpoint> read_checkpoints(ByteReader& in, uint32_t record_version);

}  // namespace mwb
