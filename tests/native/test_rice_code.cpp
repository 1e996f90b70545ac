#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "codec/BitReader.h"
#include "codec/BitWriter.h"
#include "codec/CodecError.h"
#include "codec/RiceCode.h"

namespace mwb {
namespace {

constexpr int64_t kInt64Min = std::numeric_limits<int64_t>::min();
constexpr int64_t kInt64Max = std::numeric_limits<int64_t>::max();
constexpr uint64_t kUint64Max = std::numeric_limits<uint64_t>::max();

TEST(RiceCode, ZigzagInterleavesSignsAndCoversTheFullRange) {
    EXPECT_EQ(zigzag_encode(0), 0u);
    EXPECT_EQ(zigzag_encode(-1), 1u);
    EXPECT_EQ(zigzag_encode(1), 2u);
    EXPECT_EQ(zigzag_encode(-2), 3u);
    EXPECT_EQ(zigzag_encode(kInt64Max), kUint64Max - 1);
    EXPECT_EQ(zigzag_encode(kInt64Min), kUint64Max);
    for (int64_t v : {int64_t{0}, int64_t{-1}, int64_t{7}, int64_t{-123456789}, kInt64Min, kInt64Max}) {
        EXPECT_EQ(zigzag_decode(zigzag_encode(v)), v);
    }
}

TEST(RiceCode, FixedParameterRoundTripsValuesAroundTheEscape) {
    for (unsigned k = 0; k <= kRiceMaxParameter; ++k) {
        const uint64_t escape_start = uint64_t{kRiceEscapeQuotient} << k;
        const std::vector<uint64_t> values = {0, 1, (uint64_t{1} << k) - 1, uint64_t{1} << k,
                                              escape_start - 1, escape_start, escape_start + 1,
                                              kUint64Max, kUint64Max >> 1};
        BitWriter writer;
        for (uint64_t v : values) write_rice(writer, v, k);
        BitReader reader(writer.bytes().data(), writer.bytes().size());
        for (uint64_t v : values) EXPECT_EQ(read_rice(reader, k), v) << "k " << k;
        EXPECT_NO_THROW(reader.require_end());
    }
}

TEST(RiceCode, SmallValuesCostOneBitPlusK) {
    BitWriter writer;
    write_rice(writer, 5, 3);
    EXPECT_EQ(writer.bit_count(), 4u);
    write_rice(writer, 0, 0);
    EXPECT_EQ(writer.bit_count(), 5u);
}

TEST(RiceCode, UnaryPartNeverExceedsTheEscapeLength) {
    // With k = 0 a plain code of 2^64 - 1 would need 2^64 bits; the escape bounds it.
    BitWriter writer;
    write_rice(writer, kUint64Max, 0);
    EXPECT_LE(writer.bit_count(), kRiceEscapeQuotient + 6 + 63);
}

TEST(RiceCode, SizedUintRoundTripsUpTo2To63) {
    const std::vector<uint64_t> values = {0, 1, 2, 1200, uint64_t{1} << 32, (uint64_t{1} << 63) - 1};
    BitWriter writer;
    for (uint64_t v : values) write_sized_uint(writer, v);
    BitReader reader(writer.bytes().data(), writer.bytes().size());
    for (uint64_t v : values) EXPECT_EQ(read_sized_uint(reader), v);
    EXPECT_THROW(write_sized_uint(writer, uint64_t{1} << 63), std::invalid_argument);
}

TEST(RiceCode, AdaptiveRoundTripsMixedMagnitudes) {
    std::mt19937_64 random(7);
    std::vector<int64_t> values;
    for (int i = 0; i < 4000; ++i) {
        // Runs of very different scales, including the extremes.
        const unsigned bits = 1 + static_cast<unsigned>((i / 50) % 63);
        const auto magnitude = static_cast<int64_t>(random() >> (64 - bits));
        values.push_back(random() & 1 ? magnitude : -magnitude);
    }
    values.push_back(kInt64Min);
    values.push_back(kInt64Max);
    values.push_back(0);

    BitWriter writer;
    AdaptiveRice encoder(2);
    for (int64_t v : values) encoder.write_signed(writer, v);
    BitReader reader(writer.bytes().data(), writer.bytes().size());
    AdaptiveRice decoder(2);
    for (int64_t v : values) ASSERT_EQ(decoder.read_signed(reader), v);
    EXPECT_EQ(decoder.parameter(), encoder.parameter());
}

TEST(RiceCode, AdaptiveParameterFollowsTheMagnitude) {
    BitWriter writer;
    AdaptiveRice coder(0);
    for (int i = 0; i < 64; ++i) coder.write_unsigned(writer, 1000);
    // Mean 1000 lies between 2^9 and 2^10.
    EXPECT_GE(coder.parameter(), 9u);
    EXPECT_LE(coder.parameter(), 10u);
    // The memory of old values halves every 8 values, so 128 small ones wash out the 1000s.
    for (int i = 0; i < 128; ++i) coder.write_unsigned(writer, 1);
    EXPECT_LE(coder.parameter(), 1u);
}

TEST(RiceCode, AdaptiveCodingOfLargeValuesIsCompact) {
    std::mt19937_64 random(99);
    BitWriter writer;
    AdaptiveRice coder(0);
    const int count = 1000;
    for (int i = 0; i < count; ++i) coder.write_unsigned(writer, (uint64_t{1} << 20) + random() % 1000);
    // About 21 bits of information each; a fixed small k would need tens of escape bits.
    EXPECT_LT(writer.bit_count(), size_t{count} * 24);
}

TEST(RiceCode, TruncatedInputThrows) {
    BitWriter writer;
    write_rice(writer, 123456789, 3);
    std::vector<uint8_t> bytes = writer.take_bytes();
    for (size_t size = 0; size < bytes.size(); ++size) {
        BitReader reader(bytes.data(), size);
        EXPECT_THROW(read_rice(reader, 3), CodecError) << "size " << size;
    }
}

TEST(RiceCode, NonCanonicalEscapeThrows) {
    // An escape holding the value 1, which the plain form codes in one bit.
    BitWriter writer;
    writer.write_bits(0, kRiceEscapeQuotient);
    writer.write_bits(0, 6);
    BitReader reader(writer.bytes().data(), writer.bytes().size());
    EXPECT_THROW(read_rice(reader, 0), CodecError);

    const std::vector<uint8_t> zeros(64, 0);
    BitReader zero_reader(zeros.data(), zeros.size());
    EXPECT_THROW(read_rice(zero_reader, 4), CodecError);
}

TEST(RiceCode, GarbageEitherDecodesOrThrowsCodecError) {
    std::mt19937_64 random(2024);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<uint8_t> bytes(1 + random() % 64);
        for (uint8_t& b : bytes) b = static_cast<uint8_t>(random());
        BitReader reader(bytes.data(), bytes.size());
        AdaptiveRice coder(static_cast<unsigned>(random() % 8));
        try {
            // Every code consumes at least one bit, so this ends.
            while (reader.bits_remaining() > 0) coder.read_signed(reader);
        } catch (const CodecError&) {
        }
        EXPECT_LE(coder.parameter(), kRiceMaxParameter);
    }
}

}  // namespace
}  // namespace mwb
