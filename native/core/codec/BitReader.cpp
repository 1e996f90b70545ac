#include "codec/BitReader.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "codec/CodecError.h"

namespace mwb {

uint64_t BitReader::read_bits(unsigned width) {
    if (width > 64) throw std::invalid_argument("BitReader: width above 64 bits");
    if (width > bits_remaining()) throw CodecError("unexpected end of data");
    uint64_t value = 0;
    unsigned filled = 0;
    while (filled < width) {
        const unsigned offset = bit_position_ % 8;
        const unsigned chunk = std::min(width - filled, 8u - offset);
        const uint64_t bits = (uint64_t{data_[bit_position_ / 8]} >> offset) & ((1u << chunk) - 1);
        value |= bits << filled;
        filled += chunk;
        bit_position_ += chunk;
    }
    return value;
}

double BitReader::read_double() {
    const uint64_t bits = read_bits(64);
    double value = 0;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

float BitReader::read_float() {
    const auto bits = static_cast<uint32_t>(read_bits(32));
    float value = 0;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

void BitReader::require_end() const {
    // The writer pads only the last byte, with zeros; anything else means the data is not what
    // the parser believes it is.
    const size_t remaining = bits_remaining();
    if (remaining >= 8) throw CodecError("unexpected data after the end of the track");
    if (remaining > 0 && (data_[bit_position_ / 8] >> (bit_position_ % 8)) != 0) {
        throw CodecError("non-zero padding bits");
    }
}

}  // namespace mwb
