#pragma once
// Checkpoints are stored deflated (zlib): full-precision states of every body every 0.5 s would
// otherwise outweigh the compressed motion.
#include <cstdint>
#include <string>
#include <vector>

#include "library/ByteIO.h"
#include "sim/WorldResult.h"

namespace mwb {

void write_checkpoints(ByteWriter& out, const std::vector<Checkpoint>& checkpoints, uint32_t body_count,
                       uint32_t joint_count);
/// A checkpoint block as stored, still deflated: what a loaded world keeps (see StoredWorld).
struct PackedCheckpoints {
    uint32_t record_version = 0;
    uint64_t plain_size = 0;
    std::vector<uint8_t> packed;
};
/// Takes the block without inflating it (`record_version`: the world record's version, which
/// decides the checkpoint layout); its claimed size is checked against what deflate can hold.
PackedCheckpoints read_packed_checkpoints(ByteReader& in, uint32_t record_version);
/// How many checkpoints a packed block holds, inflating only its first bytes; 0 for a damaged one.
size_t checkpoint_count(const PackedCheckpoints& block);
/// The checkpoints of a block kept packed. Throws LibraryError, naming `what`, for a damaged one.
std::vector<Checkpoint> inflate_checkpoints(const PackedCheckpoints& block, const std::string& what);

}  // namespace mwb
