#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "codec/BitReader.h"
#include "codec/BitWriter.h"
#include "codec/CodecError.h"

namespace mwb {
namespace {

uint64_t mask(unsigned width) { return width == 64 ? ~uint64_t{0} : (uint64_t{1} << width) - 1; }

// Values worth checking at each width: both ends, alternating patterns and single bits.
std::vector<uint64_t> boundary_values(unsigned width) {
    const uint64_t m = mask(width);
    std::vector<uint64_t> values = {0, m, m & 0x5555555555555555ull, m & 0xAAAAAAAAAAAAAAAAull};
    if (width > 0) {
        values.push_back(1);
        values.push_back(uint64_t{1} << (width - 1));
        values.push_back(m >> 1);
    }
    return values;
}

TEST(BitIo, EveryWidthRoundTripsBoundaryValues) {
    for (unsigned width = 0; width <= 64; ++width) {
        BitWriter writer;
        const std::vector<uint64_t> values = boundary_values(width);
        // A 3-bit prefix puts every value at an unaligned position.
        writer.write_bits(0b101, 3);
        for (uint64_t v : values) writer.write_bits(v, width);
        EXPECT_EQ(writer.bit_count(), 3 + values.size() * width);

        BitReader reader(writer.bytes().data(), writer.bytes().size());
        ASSERT_EQ(reader.read_bits(3), 0b101u);
        for (uint64_t v : values) EXPECT_EQ(reader.read_bits(width), v) << "width " << width;
        EXPECT_NO_THROW(reader.require_end());
    }
}

TEST(BitIo, BitsAboveTheWidthAreIgnored) {
    BitWriter writer;
    writer.write_bits(~uint64_t{0}, 5);
    writer.write_bits(0, 3);
    ASSERT_EQ(writer.bytes().size(), 1u);
    EXPECT_EQ(writer.bytes()[0], 0x1F);
}

TEST(BitIo, FirstBitGoesToTheLeastSignificantBit) {
    BitWriter writer;
    writer.write_bit(true);
    writer.write_bits(0b10, 2);  // least significant bit first: 0 then 1
    writer.write_bits(0x1FF, 9);
    const std::vector<uint8_t> expected = {0b11111101, 0b00001111};
    EXPECT_EQ(writer.bytes(), expected);
}

TEST(BitIo, RandomMixedSequenceRoundTrips) {
    std::mt19937_64 random(12345);
    std::vector<std::pair<unsigned, uint64_t>> items;
    BitWriter writer;
    size_t total_bits = 0;
    for (int i = 0; i < 5000; ++i) {
        const auto width = static_cast<unsigned>(random() % 65);
        const uint64_t value = random() & mask(width);
        items.emplace_back(width, value);
        writer.write_bits(value, width);
        total_bits += width;
    }
    ASSERT_EQ(writer.bit_count(), total_bits);
    ASSERT_EQ(writer.bytes().size(), (total_bits + 7) / 8);
    BitReader reader(writer.bytes().data(), writer.bytes().size());
    for (const auto& [width, value] : items) ASSERT_EQ(reader.read_bits(width), value);
    EXPECT_LT(reader.bits_remaining(), 8u);
}

TEST(BitIo, FloatingPointValuesKeepTheirExactBits) {
    const double doubles[] = {0.0, -0.0, 1.0 / 3.0, -1e300, std::numeric_limits<double>::denorm_min(),
                              std::numeric_limits<double>::infinity()};
    const float floats[] = {-4.905f / 14400.0f, std::numeric_limits<float>::max(), -0.0f};
    BitWriter writer;
    writer.write_bit(true);
    for (double d : doubles) writer.write_double(d);
    for (float f : floats) writer.write_float(f);
    BitReader reader(writer.bytes().data(), writer.bytes().size());
    reader.read_bit();
    for (double d : doubles) {
        const double read = reader.read_double();
        EXPECT_EQ(read, d);
        EXPECT_EQ(std::signbit(read), std::signbit(d));
    }
    for (float f : floats) {
        const float read = reader.read_float();
        EXPECT_EQ(read, f);
        EXPECT_EQ(std::signbit(read), std::signbit(f));
    }
}

TEST(BitIo, ReadingPastTheEndThrowsWithoutConsuming) {
    const uint8_t data[2] = {0xAB, 0xCD};
    BitReader reader(data, 2);
    EXPECT_EQ(reader.read_bits(12), 0xDABu);
    EXPECT_THROW(reader.read_bits(5), CodecError);
    EXPECT_EQ(reader.bits_remaining(), 4u);
    EXPECT_EQ(reader.read_bits(4), 0xCu);
    EXPECT_THROW(reader.read_bit(), CodecError);
    EXPECT_THROW(reader.read_double(), CodecError);
    EXPECT_EQ(reader.read_bits(0), 0u);
}

TEST(BitIo, EmptyBufferThrowsOnAnyRead) {
    BitReader reader(nullptr, 0);
    EXPECT_THROW(reader.read_bits(1), CodecError);
    EXPECT_THROW(reader.read_bits(64), CodecError);
    EXPECT_NO_THROW(reader.require_end());
}

TEST(BitIo, WidthAbove64IsAProgrammingError) {
    BitWriter writer;
    EXPECT_THROW(writer.write_bits(0, 65), std::invalid_argument);
    const uint8_t data[16] = {};
    BitReader reader(data, sizeof data);
    EXPECT_THROW(reader.read_bits(65), std::invalid_argument);
}

TEST(BitIo, RequireEndRejectsTrailingDataAndDirtyPadding) {
    const uint8_t two_bytes[2] = {0x01, 0x00};
    BitReader long_reader(two_bytes, 2);
    long_reader.read_bit();
    EXPECT_THROW(long_reader.require_end(), CodecError);

    const uint8_t dirty[1] = {0x81};
    BitReader dirty_reader(dirty, 1);
    dirty_reader.read_bit();
    EXPECT_THROW(dirty_reader.require_end(), CodecError);

    const uint8_t clean[1] = {0x01};
    BitReader clean_reader(clean, 1);
    clean_reader.read_bit();
    EXPECT_NO_THROW(clean_reader.require_end());
}

TEST(BitIo, TakeBytesEmptiesTheWriter) {
    BitWriter writer;
    writer.write_bits(0x3FF, 10);
    const std::vector<uint8_t> bytes = writer.take_bytes();
    EXPECT_EQ(bytes.size(), 2u);
    EXPECT_EQ(writer.bit_count(), 0u);
    EXPECT_TRUE(writer.bytes().empty());
}

}  // namespace
}  // namespace mwb
