#include "codec/RiceCode.h"

#include <algorithm>
#include <stdexcept>

#include "codec/BitReader.h"
#include "codec/BitWriter.h"
#include "codec/CodecError.h"

namespace mwb {
namespace {

constexpr unsigned kLengthFieldBits = 6;
constexpr uint64_t kAdaptiveMagnitudeCap = uint64_t{1} << 48;
constexpr uint64_t kAdaptiveWindow = 16;

unsigned bit_length(uint64_t value) {
    unsigned length = 0;
    while (value != 0) {
        value >>= 1;
        ++length;
    }
    return length;
}

// The n - 1 bits below the leading 1 of a value of bit length n >= 1.
void write_below_leading_one(BitWriter& writer, uint64_t value, unsigned length) {
    writer.write_bits(value, length - 1);
}

uint64_t read_below_leading_one(BitReader& reader, unsigned length) {
    return (uint64_t{1} << (length - 1)) | reader.read_bits(length - 1);
}

}  // namespace

uint64_t zigzag_encode(int64_t value) {
    const auto bits = static_cast<uint64_t>(value);
    return value < 0 ? ~(bits << 1) : bits << 1;
}

int64_t zigzag_decode(uint64_t value) {
    return static_cast<int64_t>((value >> 1) ^ (~(value & 1) + 1));
}

void write_rice(BitWriter& writer, uint64_t value, unsigned k) {
    if (k > kRiceMaxParameter) throw std::invalid_argument("write_rice: parameter too large");
    const uint64_t quotient = value >> k;
    if (quotient < kRiceEscapeQuotient) {
        writer.write_bits(0, static_cast<unsigned>(quotient));
        writer.write_bit(true);
        writer.write_bits(value, k);
        return;
    }
    writer.write_bits(0, kRiceEscapeQuotient);
    const unsigned length = bit_length(value);
    writer.write_bits(length - 1, kLengthFieldBits);
    write_below_leading_one(writer, value, length);
}

uint64_t read_rice(BitReader& reader, unsigned k) {
    if (k > kRiceMaxParameter) throw std::invalid_argument("read_rice: parameter too large");
    unsigned quotient = 0;
    while (quotient < kRiceEscapeQuotient && !reader.read_bit()) ++quotient;
    if (quotient < kRiceEscapeQuotient) return (uint64_t{quotient} << k) | reader.read_bits(k);
    const unsigned length = static_cast<unsigned>(reader.read_bits(kLengthFieldBits)) + 1;
    const uint64_t value = read_below_leading_one(reader, length);
    if ((value >> k) < kRiceEscapeQuotient) throw CodecError("non-canonical Rice escape");
    return value;
}

void write_sized_uint(BitWriter& writer, uint64_t value) {
    const unsigned length = bit_length(value);
    if (length >= (1u << kLengthFieldBits)) {
        throw std::invalid_argument("write_sized_uint: value must be below 2^63");
    }
    writer.write_bits(length, kLengthFieldBits);
    if (length > 0) write_below_leading_one(writer, value, length);
}

uint64_t read_sized_uint(BitReader& reader) {
    const auto length = static_cast<unsigned>(reader.read_bits(kLengthFieldBits));
    return length == 0 ? 0 : read_below_leading_one(reader, length);
}

AdaptiveRice::AdaptiveRice(unsigned initial_k)
    : magnitude_sum_(uint64_t{1} << std::min(initial_k, kRiceMaxParameter)),
      parameter_(std::min(initial_k, kRiceMaxParameter)) {}

void AdaptiveRice::write_unsigned(BitWriter& writer, uint64_t value) {
    write_rice(writer, value, parameter_);
    update(value);
}

void AdaptiveRice::write_signed(BitWriter& writer, int64_t value) {
    write_unsigned(writer, zigzag_encode(value));
}

uint64_t AdaptiveRice::read_unsigned(BitReader& reader) {
    const uint64_t value = read_rice(reader, parameter_);
    update(value);
    return value;
}

int64_t AdaptiveRice::read_signed(BitReader& reader) { return zigzag_decode(read_unsigned(reader)); }

void AdaptiveRice::update(uint64_t value) {
    // The cap keeps the sum far from overflow; values that large are escaped anyway.
    magnitude_sum_ += std::min(value, kAdaptiveMagnitudeCap);
    if (++count_ == kAdaptiveWindow) {
        magnitude_sum_ >>= 1;
        count_ >>= 1;
    }
    unsigned k = 0;
    while (k < kRiceMaxParameter && (count_ << k) < magnitude_sum_) ++k;
    parameter_ = k;
}

}  // namespace mwb
