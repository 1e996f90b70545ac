// Fuzz target: a library file image must load or be refused with LibraryError, and every world
// it accepts must decode or fail with CodecError; never a crash, hang or out-of-bounds read. Each
// input is read twice: as it is, and with every record's checksum repaired, since a mutation
// nearly always breaks a checksum and would otherwise never reach the record and track decoders.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "codec/CodecError.h"
#include "library/ByteIO.h"
#include "library/FileBytes.h"
#include "library/LibraryFormat.h"
#include "library/LibraryReader.h"
#include "library/WorldDecoding.h"

namespace {

uint32_t u32_at(const std::vector<uint8_t>& bytes, size_t at) {
    uint32_t value = 0;
    std::memcpy(&value, &bytes[at], 4);  // the format is little-endian, as are fuzzing hosts
    return value;
}

// The image with each record's checksum recomputed, up to the first record whose frame is broken
// (see LibraryFormat.h for the layout).
std::vector<uint8_t> with_repaired_checksums(std::vector<uint8_t> bytes) {
    if (bytes.size() < 16) return bytes;
    size_t at = 16 + size_t{u32_at(bytes, 12)} + 4;
    while (at <= bytes.size() && bytes.size() - at >= mwb::kRecordHeaderBytes) {
        const uint32_t payload_size = u32_at(bytes, at + 12);
        if (u32_at(bytes, at) != mwb::kRecordMagic || payload_size > bytes.size() - at - mwb::kRecordHeaderBytes) break;
        const uint32_t crc = mwb::crc32_of(&bytes[at + mwb::kRecordHeaderBytes], payload_size,
                                           mwb::crc32_of(&bytes[at + 4], 12));
        std::memcpy(&bytes[at + 16], &crc, 4);
        at += mwb::kRecordHeaderBytes + payload_size;
    }
    return bytes;
}

void read_and_decode(const std::vector<uint8_t>& image) {
    try {
        const mwb::LibraryReader reader("fuzz.mwb", image);
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
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::vector<uint8_t> image(data, data + size);
    read_and_decode(image);
    read_and_decode(with_repaired_checksums(image));
    return 0;
}
