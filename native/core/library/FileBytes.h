#pragma once
// Whole-file and tail reads with errors that name the file.
#include <cstdint>
#include <string>
#include <vector>

namespace mwb {

/// Bytes of `path` from `offset` to its current end. Throws LibraryError if it cannot be read.
std::vector<uint8_t> read_file_from(const std::string& path, uint64_t offset);
/// The first `max_bytes` of `path` (fewer when the file is shorter). Throws LibraryError if it
/// cannot be read.
std::vector<uint8_t> read_file_prefix(const std::string& path, size_t max_bytes);
/// Whether `path` is a file with at least one byte in it.
bool file_holds_bytes(const std::string& path);
/// crc32 (zlib) of a byte range, continuing from `crc`.
uint32_t crc32_of(const uint8_t* data, size_t size, uint32_t crc = 0);

}  // namespace mwb
