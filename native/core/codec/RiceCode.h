#pragma once
// Integer codes for the motion codec.
//
// Rice code with parameter k of an unsigned value u: the quotient u >> k as that many 0 bits and
// a terminating 1 bit, then the low k bits of u. A quotient of kRiceEscapeQuotient or more is
// escaped instead: kRiceEscapeQuotient 0 bits, the bit length n of u in 6 bits (as n - 1), then
// the n - 1 bits of u below its leading 1. The unary part is therefore never longer than
// kRiceEscapeQuotient bits, whatever the input, and every value up to 2^64 - 1 is codable.
// Signed values go through the zigzag map 0, -1, 1, -2, 2, ... -> 0, 1, 2, 3, 4, ...
#include <cstdint>

namespace mwb {

class BitWriter;
class BitReader;

/// Longest unary run of a Rice code; longer quotients use the escape form.
constexpr unsigned kRiceEscapeQuotient = 8;
/// Largest Rice parameter the adaptive rule selects.
constexpr unsigned kRiceMaxParameter = 56;

uint64_t zigzag_encode(int64_t value);
int64_t zigzag_decode(uint64_t value);

/// Writes `value` as a Rice code with parameter `k` (0..kRiceMaxParameter).
void write_rice(BitWriter& writer, uint64_t value, unsigned k);
/// Reads a Rice code with parameter `k`. Throws CodecError on truncated data or a non-canonical
/// escape (one whose value would have fitted the plain form).
uint64_t read_rice(BitReader& reader, unsigned k);

/// Writes `value` (< 2^63) as its bit length n in 6 bits followed by the n - 1 bits below its
/// leading 1; 0 costs 6 bits. Used for header fields with no useful prior.
void write_sized_uint(BitWriter& writer, uint64_t value);
/// Reads a value written by write_sized_uint. Throws CodecError on truncated data.
uint64_t read_sized_uint(BitReader& reader);

/// Rice coding with a parameter that follows the data: k is the smallest value with
/// count << k >= magnitude_sum, where magnitude_sum adds each coded (zigzagged) value, capped at
/// 2^48, and both sums are halved whenever count reaches 16. This tracks the mean of roughly the
/// last 16 values. The rule uses integers only, so an encoder and a decoder that code the same
/// values see the same sequence of parameters on every machine.
class AdaptiveRice {
public:
    /// Starts as if the recent mean magnitude were 2^initial_k.
    explicit AdaptiveRice(unsigned initial_k);

    /// Current Rice parameter k.
    unsigned parameter() const { return parameter_; }

    void write_unsigned(BitWriter& writer, uint64_t value);
    void write_signed(BitWriter& writer, int64_t value);
    /// Throws CodecError like read_rice.
    uint64_t read_unsigned(BitReader& reader);
    int64_t read_signed(BitReader& reader);

private:
    void update(uint64_t value);

    uint64_t magnitude_sum_;
    uint64_t count_ = 1;
    unsigned parameter_;
};

}  // namespace mwb
