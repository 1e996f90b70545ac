#pragma once
// The .mwb library file layout (all integers little-endian):
//
//   file   := magic[8] u32:format_version u32:header_size header_json[header_size]
//             u32:crc32(header_json) record*
//   record := u32:kRecordMagic u32:type u32:version u32:payload_size
//             u32:crc32(type, version, payload_size, payload) payload[payload_size]
//
// Records are appended whole, one write each, as worlds finish; a crash can only leave the last
// record incomplete. Type and version values are never reassigned to another meaning.
#include <cstdint>

namespace mwb {

constexpr char kLibraryMagic[8] = {'\x89', 'M', 'W', 'B', '\r', '\n', '\x1a', '\n'};
constexpr uint32_t kLibraryFormatVersion = 1;
constexpr uint32_t kRecordMagic = 0x4352574Du;  // "MWRC"
constexpr uint32_t kRecordTypeWorld = 1;
constexpr uint32_t kRecordTypeRejection = 2;
constexpr uint32_t kRecordTypeSceneRevision = 3;
constexpr uint32_t kRecordHeaderBytes = 20;
/// Larger payloads are corruption; guards allocations driven by a damaged size field.
constexpr uint32_t kMaxRecordPayloadBytes = 1u << 30;
constexpr uint32_t kMaxHeaderBytes = 1u << 30;

}  // namespace mwb
