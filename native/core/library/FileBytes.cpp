#include "library/FileBytes.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "library/ByteIO.h"

namespace mwb {

std::vector<uint8_t> read_file_from(const std::string& path, uint64_t offset) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw LibraryError(path + ": cannot open (" + std::strerror(errno) + ")");
    const auto end = static_cast<uint64_t>(in.tellg());
    if (offset > end) throw LibraryError(path + ": file shrank below byte " + std::to_string(offset));
    std::vector<uint8_t> bytes(end - offset);
    in.seekg(static_cast<std::streamoff>(offset));
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (static_cast<uint64_t>(in.gcount()) != bytes.size()) throw LibraryError(path + ": read failed");
    return bytes;
}

std::vector<uint8_t> read_file_prefix(const std::string& path, size_t max_bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw LibraryError(path + ": cannot open (" + std::strerror(errno) + ")");
    std::vector<uint8_t> bytes(max_bytes);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<size_t>(in.gcount()));
    return bytes;
}

bool file_holds_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    return in && in.tellg() > 0;
}

uint32_t crc32_of(const uint8_t* data, size_t size, uint32_t crc) {
    // zlib's crc32 takes a uInt length; feed large buffers in chunks.
    while (size > 0) {
        const uInt chunk = static_cast<uInt>(std::min<size_t>(size, 1u << 30));
        crc = static_cast<uint32_t>(::crc32(crc, data, chunk));
        data += chunk;
        size -= chunk;
    }
    return crc;
}

}  // namespace mwb
