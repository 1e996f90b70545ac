// Fuzz target: a library file image must load or be refused with LibraryError, and every world
// it accepts must decode or fail with CodecError; never a crash, hang or out-of-bounds read.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/CodecError.h"
#include "library/ByteIO.h"
#include "library/LibraryReader.h"
#include "library/WorldDecoding.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const mwb::LibraryReader reader("fuzz.mwb", std::vector<uint8_t>(data, data + size));
        for (const mwb::StoredWorld& world : reader.worlds()) {
            try {
                mwb::decode_world_positions(world);
                mwb::decode_world_orientations(world);
                if (!world.tracks.empty() && world.frame_count > 0) mwb::decode_pose(world, 0, world.frame_count - 1);
            } catch (const mwb::CodecError&) {
            }
        }
    } catch (const mwb::LibraryError&) {
    }
    return 0;
}
