#pragma once
// Bit-level output. Bit order is LSB-first: bits fill each byte from its least significant bit
// upwards, and a multi-bit value is emitted starting with its least significant bit. The final
// byte is padded with zero bits.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mwb {

class BitWriter {
public:
    /// Appends the low `width` bits of `value`; `width` is 0..64 and higher bits are ignored.
    /// Throws std::invalid_argument when `width` > 64.
    void write_bits(uint64_t value, unsigned width);
    void write_bit(bool bit) { write_bits(bit ? 1u : 0u, 1); }
    /// Appends the IEEE-754 binary64 bit pattern of `value` (64 bits).
    void write_double(double value);
    /// Appends the IEEE-754 binary32 bit pattern of `value` (32 bits).
    void write_float(float value);

    /// Number of bits written so far.
    size_t bit_count() const { return bit_count_; }
    /// The bytes written so far, the last one zero-padded; ceil(bit_count() / 8) bytes.
    const std::vector<uint8_t>& bytes() const { return bytes_; }
    /// Moves the written bytes out; the writer is empty afterwards.
    std::vector<uint8_t> take_bytes();

private:
    std::vector<uint8_t> bytes_;
    size_t bit_count_ = 0;
};

}  // namespace mwb
