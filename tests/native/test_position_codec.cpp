#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "codec/CodecError.h"
#include "codec/PositionDecoder.h"
#include "codec/PositionEncoder.h"
#include "common/Math.h"

namespace mwb {
namespace {

constexpr double kDt = 1.0 / 120;
const Vec3 kGravity{0, 0, -9.81};
const double kBounds[] = {1e-4, 1e-3, 1e-2};

/// Flat (frames, 3) positions, metres.
using Track = std::vector<double>;

uint32_t frames_of(const Track& xyz) { return static_cast<uint32_t>(xyz.size() / 3); }

void push(Track& xyz, const Vec3& p) { xyz.insert(xyz.end(), p.begin(), p.end()); }

Vec3 frame_of(const Track& xyz, uint32_t i) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }

Track ballistic(uint32_t frames, const Vec3& p0, const Vec3& v0, const Vec3& gravity) {
    Track xyz;
    for (uint32_t i = 0; i < frames; ++i) {
        const double t = i * kDt;
        push(xyz, add(add(p0, scale(v0, t)), scale(gravity, t * t / 2)));
    }
    return xyz;
}

/// A ball drifting sideways and bouncing on z = 0 with restitution 0.7 until it settles.
/// Returns the positions and, in `bounces`, how many impacts happened.
Track bouncing_ball(uint32_t frames, int& bounces) {
    const double restitution = 0.7;
    double flight_start_s = 0, vz = 0, z0 = 2.0;
    bool resting = false;
    bounces = 0;
    Track xyz;
    for (uint32_t i = 0; i < frames; ++i) {
        const double t = i * kDt;
        // Advance through every impact before t; the ball stops once impacts get too soft.
        double landing_s = flight_start_s + (vz + std::sqrt(vz * vz + 2 * 9.81 * z0)) / 9.81;
        while (!resting && landing_s <= t) {
            const double impact_speed = 9.81 * (landing_s - flight_start_s) - vz;
            ++bounces;
            flight_start_s = landing_s;
            z0 = 0;
            vz = restitution * impact_speed;
            resting = vz < 0.5;
            landing_s = flight_start_s + 2 * vz / 9.81;
        }
        const double s = t - flight_start_s;
        const double z = resting ? 0.0 : z0 + vz * s - 9.81 * s * s / 2;
        push(xyz, {0.3 + 1.5 * t, -0.2 * t, z});
    }
    return xyz;
}

Track random_walk(uint32_t frames, double step_m, uint64_t seed) {
    std::mt19937_64 random(seed);
    std::normal_distribution<double> normal(0.0, step_m);
    Vec3 p{0.5, -1.0, 3.0};
    Track xyz;
    for (uint32_t i = 0; i < frames; ++i) {
        push(xyz, p);
        p = add(p, {normal(random), normal(random), normal(random)});
    }
    return xyz;
}

/// Still for 100 frames at a time, then a jump; one jump goes 1e11 m away, beyond what a
/// quantized segment can reach.
Track teleports(uint32_t frames) {
    std::mt19937_64 random(5);
    std::uniform_real_distribution<double> uniform(-50, 50);
    Vec3 p{1, 2, 3};
    Track xyz;
    for (uint32_t i = 0; i < frames; ++i) {
        if (i % 100 == 99) p = {uniform(random), uniform(random), uniform(random)};
        if (i == 450) p = {1e11, -3e10, 7.0};
        push(xyz, p);
    }
    return xyz;
}

Track rest(uint32_t frames, const Vec3& p) {
    Track xyz;
    for (uint32_t i = 0; i < frames; ++i) push(xyz, p);
    return xyz;
}

/// Circular motion (radius 2 m, one turn per second): curved, but not by gravity.
Track circle(uint32_t frames) {
    Track xyz;
    for (uint32_t i = 0; i < frames; ++i) {
        const double angle = 2 * M_PI * i * kDt;
        push(xyz, {2 * std::cos(angle), 2 * std::sin(angle), 0.5});
    }
    return xyz;
}

std::string bound_key(double bound) {
    std::ostringstream key;
    key << "bytes_at_" << bound;
    return key.str();
}

/// Decodes `bytes` and checks every frame against `xyz` (Euclidean distance <= error_max_m) and
/// that sample() reproduces decode_all() exactly.
void expect_within_bound(const std::vector<uint8_t>& bytes, const Track& xyz, double error_max_m) {
    const PositionTrackDecoder decoder(bytes);
    ASSERT_EQ(decoder.frame_count(), frames_of(xyz));
    Track decoded(xyz.size());
    decoder.decode_all(decoded.data());
    for (uint32_t i = 0; i < decoder.frame_count(); ++i) {
        const double error = norm(sub(frame_of(decoded, i), frame_of(xyz, i)));
        ASSERT_LE(error, error_max_m) << "frame " << i;
        const Vec3 sampled = decoder.sample(i);
        ASSERT_EQ(sampled, frame_of(decoded, i)) << "frame " << i;
    }
}

PositionTrackDecoder round_trip(const Track& xyz, double error_max_m, size_t* size = nullptr) {
    const std::vector<uint8_t> bytes =
        encode_position_track(xyz.data(), frames_of(xyz), kDt, kGravity, error_max_m);
    expect_within_bound(bytes, xyz, error_max_m);
    // Sizes show up in the XML report (--gtest_output=xml) for tuning.
    ::testing::Test::RecordProperty(bound_key(error_max_m), int(bytes.size()));
    if (size) *size = bytes.size();
    return PositionTrackDecoder(bytes);
}

TEST(PositionCodec, BallisticFlightIsOneSegment) {
    const Track xyz = ballistic(300, {1.0, -2.0, 0.5}, {2.0, 1.0, 6.0}, kGravity);
    for (double bound : kBounds) {
        size_t size = 0;
        EXPECT_EQ(round_trip(xyz, bound, &size).segment_count(), 1u) << "bound " << bound;
        EXPECT_LT(size, 48u);
    }
}

TEST(PositionCodec, GravityCanPointAnywhere) {
    const Vec3 sideways{-9.81, 0, 0};
    const Track xyz = ballistic(240, {0, 0, 1}, {3, 0, 0}, sideways);
    const std::vector<uint8_t> bytes =
        encode_position_track(xyz.data(), frames_of(xyz), kDt, sideways, 1e-3);
    expect_within_bound(bytes, xyz, 1e-3);
    EXPECT_EQ(PositionTrackDecoder(bytes).segment_count(), 1u);
}

TEST(PositionCodec, BouncingBallNeedsAboutTwoSegmentsPerBounce) {
    int bounces = 0;
    const Track xyz = bouncing_ball(1200, bounces);
    ASSERT_GE(bounces, 4);
    for (double bound : kBounds) {
        EXPECT_LE(round_trip(xyz, bound).segment_count(), size_t(2 * bounces + 3))
            << "bound " << bound;
    }
}

TEST(PositionCodec, RandomWalkStaysWithinBound) {
    const Track xyz = random_walk(1200, 0.005, 11);
    for (double bound : kBounds) round_trip(xyz, bound);
}

TEST(PositionCodec, TeleportsStayWithinBound) {
    const Track xyz = teleports(1200);
    for (double bound : kBounds) round_trip(xyz, bound);
    round_trip(xyz, 1e-9);
}

TEST(PositionCodec, CircularMotionStaysWithinBound) {
    const Track xyz = circle(600);
    for (double bound : kBounds) round_trip(xyz, bound);
}

TEST(PositionCodec, ArcsAreCoveredByLongerSegmentsThanChords) {
    // A link's centre 0.125 m from its joint, swinging round at half a turn per second, is
    // accelerated sideways all the time. A straight segment is a chord, whose middle sags
    // r (1 - cos(a / 2)) from an arc of angle a, so within the bound it spans at most
    // a = 2 acos(1 - e / r); curved segments must cover at least twice that.
    const double radius_m = 0.125, turn_rad_per_frame = M_PI * kDt;
    Track xyz;
    for (uint32_t i = 0; i < 600; ++i) {
        const double angle = turn_rad_per_frame * i;
        push(xyz, {0.4 + radius_m * std::sin(angle), -1.0, 3.0 - radius_m * std::cos(angle)});
    }
    for (double bound : kBounds) {
        const double chord_frames = 2 * std::acos(1 - bound / radius_m) / turn_rad_per_frame;
        const double straight_segments = (frames_of(xyz) - 1) / std::max(1.0, chord_frames);
        EXPECT_LT(double(round_trip(xyz, bound).segment_count()), straight_segments / 2) << "bound " << bound;
    }
}

TEST(PositionCodec, RestingBodyCostsAFewBytes) {
    const Track xyz = rest(1200, {1.25, -3.5, 0.75});
    for (double bound : kBounds) {
        size_t size = 0;
        EXPECT_EQ(round_trip(xyz, bound, &size).segment_count(), 1u);
        EXPECT_LT(size, 16u) << "bound " << bound;
    }
}

TEST(PositionCodec, ExtremeCoordinatesUseExactEscapes) {
    // Far beyond what a quantized start key or segment can reach with a 1e-9 m bound.
    Track xyz = rest(10, {3e17, -1e18, 0.25});
    push(xyz, {-2e17, 5e16, 1e15});
    push(xyz, {0, 0, 0});
    round_trip(xyz, 1e-9);
}

TEST(PositionCodec, ShortTracks) {
    for (uint32_t frames : {0u, 1u, 2u, 3u}) {
        const Track xyz = ballistic(frames, {4, 5, 6}, {1, 0, 0}, kGravity);
        const PositionTrackDecoder decoder = round_trip(xyz, 1e-3);
        EXPECT_EQ(decoder.frame_count(), frames);
        EXPECT_THROW(decoder.sample(frames), std::out_of_range);
    }
}

TEST(PositionCodec, RejectsInvalidInput) {
    Track xyz = rest(5, {0, 0, 0});
    EXPECT_THROW(encode_position_track(xyz.data(), 5, kDt, kGravity, 0.0), std::invalid_argument);
    EXPECT_THROW(encode_position_track(xyz.data(), 5, kDt, kGravity, NAN), std::invalid_argument);
    EXPECT_THROW(encode_position_track(xyz.data(), 5, 0.0, kGravity, 1e-3), std::invalid_argument);
    EXPECT_THROW(encode_position_track(nullptr, 5, kDt, kGravity, 1e-3), std::invalid_argument);
    EXPECT_THROW(encode_position_track(xyz.data(), 5, kDt, {0, 0, NAN}, 1e-3), std::invalid_argument);
    xyz[7] = INFINITY;
    EXPECT_THROW(encode_position_track(xyz.data(), 5, kDt, kGravity, 1e-3), std::invalid_argument);
}

TEST(PositionCodec, RejectsOtherTrackKinds) {
    Track xyz = rest(5, {0, 0, 0});
    std::vector<uint8_t> bytes = encode_position_track(xyz.data(), 5, kDt, kGravity, 1e-3);
    bytes[0] ^= 0x02;
    EXPECT_THROW(PositionTrackDecoder{bytes}, CodecError);
    EXPECT_THROW(PositionTrackDecoder(nullptr, 0), CodecError);
}

TEST(PositionCodec, EveryTruncationThrows) {
    int bounces = 0;
    const Track xyz = bouncing_ball(600, bounces);
    const std::vector<uint8_t> bytes =
        encode_position_track(xyz.data(), frames_of(xyz), kDt, kGravity, 1e-3);
    for (size_t size = 0; size < bytes.size(); ++size) {
        EXPECT_THROW(PositionTrackDecoder(bytes.data(), size), CodecError) << "size " << size;
    }
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0);
    EXPECT_THROW(PositionTrackDecoder{longer}, CodecError);
}

// Decodes possibly corrupted bytes: either CodecError, or finite frames (never a crash or hang).
void expect_safe_decode(const std::vector<uint8_t>& bytes, uint32_t original_frames) {
    try {
        const PositionTrackDecoder decoder(bytes);
        if (decoder.frame_count() > 4 * original_frames + 16) return;
        Track decoded(3 * size_t{decoder.frame_count()});
        decoder.decode_all(decoded.data());
        for (double value : decoded) ASSERT_TRUE(std::isfinite(value));
        if (decoder.frame_count() > 0) {
            const uint32_t last = decoder.frame_count() - 1;
            EXPECT_EQ(decoder.sample(last), frame_of(decoded, last));
        }
    } catch (const CodecError&) {
    }
}

TEST(PositionCodec, BitFlipsNeverCrash) {
    // Gravity segments (a bouncing ball) and curved ones (a circle).
    int bounces = 0;
    for (const Track& xyz : {bouncing_ball(600, bounces), circle(240)}) {
        const std::vector<uint8_t> bytes =
            encode_position_track(xyz.data(), frames_of(xyz), kDt, kGravity, 1e-3);
        for (size_t bit = 0; bit < 8 * bytes.size(); ++bit) {
            std::vector<uint8_t> flipped = bytes;
            flipped[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
            expect_safe_decode(flipped, frames_of(xyz));
        }
    }
}

TEST(PositionCodec, RandomBytesNeverCrash) {
    std::mt19937_64 random(77);
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<uint8_t> bytes(1 + random() % 48);
        for (uint8_t& b : bytes) b = static_cast<uint8_t>(random());
        // A valid tag (of either format) gets the parser past the first check.
        bytes[0] = trial % 2 ? kPositionTrackFormatV1 : kPositionTrackFormatV2;
        expect_safe_decode(bytes, 1000);
    }
}

}  // namespace
}  // namespace mwb
