#include "codec/BitWriter.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace mwb {

void BitWriter::write_bits(uint64_t value, unsigned width) {
    if (width > 64) throw std::invalid_argument("BitWriter: width above 64 bits");
    while (width > 0) {
        const unsigned offset = bit_count_ % 8;
        if (offset == 0) bytes_.push_back(0);
        const unsigned chunk = std::min(width, 8u - offset);
        const uint64_t chunk_mask = (uint64_t{1} << chunk) - 1;
        bytes_.back() = static_cast<uint8_t>(bytes_.back() | ((value & chunk_mask) << offset));
        // chunk <= 8, so the shift is always defined.
        value >>= chunk;
        width -= chunk;
        bit_count_ += chunk;
    }
}

void BitWriter::write_double(double value) {
    uint64_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    write_bits(bits, 64);
}

void BitWriter::write_float(float value) {
    uint32_t bits = 0;
    std::memcpy(&bits, &value, sizeof bits);
    write_bits(bits, 32);
}

std::vector<uint8_t> BitWriter::take_bytes() {
    bit_count_ = 0;
    return std::exchange(bytes_, {});
}

}  // namespace mwb
