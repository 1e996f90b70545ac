#pragma once
// Bit-level input matching BitWriter (LSB-first). Every read checks the remaining length first and
// throws CodecError instead of reading past the end, so corrupted input is always safe to parse.
#include <cstddef>
#include <cstdint>

namespace mwb {

class BitReader {
public:
    /// Reads from `size` bytes at `data`; the buffer must outlive the reader. `data` may be null
    /// when `size` is 0.
    BitReader(const uint8_t* data, size_t size) : data_(data), bit_size_(size * 8) {}

    /// Reads `width` bits (0..64) as written by BitWriter::write_bits. Throws CodecError when
    /// fewer than `width` bits remain (nothing is consumed then) and std::invalid_argument when
    /// `width` > 64.
    uint64_t read_bits(unsigned width);
    bool read_bit() { return read_bits(1) != 0; }
    /// Reads a binary64 bit pattern; the value may be NaN or infinite, callers validate it.
    double read_double();
    /// Reads a binary32 bit pattern; the value may be NaN or infinite, callers validate it.
    float read_float();

    size_t bits_remaining() const { return bit_size_ - bit_position_; }
    /// Throws CodecError unless only the zero padding of the last byte remains.
    void require_end() const;

private:
    const uint8_t* data_;
    size_t bit_size_;
    size_t bit_position_ = 0;
};

}  // namespace mwb
