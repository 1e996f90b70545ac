#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "codec/CodecError.h"
#include "codec/RotationDecoder.h"
#include "codec/RotationEncoder.h"
#include "common/Math.h"

namespace mwb {
namespace {

constexpr double kDt = 1.0 / 120;
constexpr double kDegree = M_PI / 180;
const double kBounds[] = {0.1 * kDegree, 0.5 * kDegree, 1 * kDegree, 5 * kDegree};

/// Flat (frames, 4) quaternions (w, x, y, z).
using Track = std::vector<double>;

uint32_t frames_of(const Track& wxyz) { return static_cast<uint32_t>(wxyz.size() / 4); }

void push(Track& wxyz, const Quat& q) { wxyz.insert(wxyz.end(), q.begin(), q.end()); }

Quat frame_of(const Track& wxyz, uint32_t i) {
    return {wxyz[4 * i], wxyz[4 * i + 1], wxyz[4 * i + 2], wxyz[4 * i + 3]};
}

Vec3 unit(const Vec3& v) { return scale(v, 1 / norm(v)); }

/// Angle of the rotation between a and b, radians; accurate for tiny angles, sign-blind.
double angle_between(const Quat& a, const Quat& b) {
    const Quat r = quat_multiply(quat_normalized(a), quat_conjugate(quat_normalized(b)));
    return 2 * std::atan2(std::sqrt(r[1] * r[1] + r[2] * r[2] + r[3] * r[3]), std::fabs(r[0]));
}

/// Constant angular velocity `rate_rad_s` about a fixed world axis.
Track spin(uint32_t frames, const Vec3& axis, double rate_rad_s, const Quat& q0) {
    Track wxyz;
    for (uint32_t i = 0; i < frames; ++i) {
        push(wxyz, quat_multiply(quat_from_axis_angle(unit(axis), rate_rad_s * i * kDt), q0));
    }
    return wxyz;
}

/// Torque-free asymmetric body spun near its intermediate axis (it flips over periodically),
/// integrated with RK4 at 16 substeps per frame.
Track tumbling(uint32_t frames) {
    const Vec3 inertia{1.0, 2.0, 3.0};
    Vec3 omega{0.05, 6.0, 0.05};  // body frame, rad/s
    Quat q = quat_from_euler_xyz({0.3, -0.2, 1.0});
    const auto derivative = [&](const Quat& qq, const Vec3& w, Quat& dq, Vec3& dw) {
        const Quat half = quat_multiply(qq, Quat{0, w[0], w[1], w[2]});
        dq = {half[0] / 2, half[1] / 2, half[2] / 2, half[3] / 2};
        dw = {(inertia[1] - inertia[2]) * w[1] * w[2] / inertia[0],
              (inertia[2] - inertia[0]) * w[2] * w[0] / inertia[1],
              (inertia[0] - inertia[1]) * w[0] * w[1] / inertia[2]};
    };
    const auto step = [](const Quat& qq, const Quat& dq, double h) {
        return Quat{qq[0] + h * dq[0], qq[1] + h * dq[1], qq[2] + h * dq[2], qq[3] + h * dq[3]};
    };
    const int substeps = 16;
    const double h = kDt / substeps;
    Track wxyz;
    for (uint32_t i = 0; i < frames; ++i) {
        push(wxyz, q);
        for (int s = 0; s < substeps; ++s) {
            Quat k1q, k2q, k3q, k4q;
            Vec3 k1w, k2w, k3w, k4w;
            derivative(q, omega, k1q, k1w);
            derivative(step(q, k1q, h / 2), add(omega, scale(k1w, h / 2)), k2q, k2w);
            derivative(step(q, k2q, h / 2), add(omega, scale(k2w, h / 2)), k3q, k3w);
            derivative(step(q, k3q, h), add(omega, scale(k3w, h)), k4q, k4w);
            for (int c = 0; c < 4; ++c) q[c] += h / 6 * (k1q[c] + 2 * k2q[c] + 2 * k3q[c] + k4q[c]);
            for (int c = 0; c < 3; ++c) {
                omega[c] += h / 6 * (k1w[c] + 2 * k2w[c] + 2 * k3w[c] + k4w[c]);
            }
            q = quat_normalized(q);
        }
    }
    return wxyz;
}

/// An independent uniformly random orientation every frame: nothing to predict.
Track random_orientations(uint32_t frames, uint64_t seed) {
    std::mt19937_64 random(seed);
    std::normal_distribution<double> normal;
    Track wxyz;
    for (uint32_t i = 0; i < frames; ++i) {
        push(wxyz, quat_normalized({normal(random), normal(random), normal(random), normal(random)}));
    }
    return wxyz;
}

/// Still for 150 frames at a time, then a jump of up to 180 degrees.
Track jumps(uint32_t frames) {
    Track wxyz;
    Quat q{1, 0, 0, 0};
    for (uint32_t i = 0; i < frames; ++i) {
        if (i % 150 == 149) q = quat_multiply(quat_from_axis_angle(unit({1, 2, -1}), M_PI - 0.01 * i), q);
        push(wxyz, q);
    }
    return wxyz;
}

Track rest(uint32_t frames, const Quat& q) {
    Track wxyz;
    for (uint32_t i = 0; i < frames; ++i) push(wxyz, q);
    return wxyz;
}

std::string bound_key(double bound) {
    std::ostringstream key;
    key << "bytes_at_" << bound;
    return key.str();
}

/// Decodes `bytes` and checks every frame against `wxyz` (relative angle <= error_max_rad), that
/// decoded quaternions are unit, and that sample() reproduces decode_all() exactly.
void expect_within_bound(const std::vector<uint8_t>& bytes, const Track& wxyz,
                         double error_max_rad) {
    const RotationTrackDecoder decoder(bytes);
    ASSERT_EQ(decoder.frame_count(), frames_of(wxyz));
    Track decoded(wxyz.size());
    decoder.decode_all(decoded.data());
    for (uint32_t i = 0; i < decoder.frame_count(); ++i) {
        const Quat q = frame_of(decoded, i);
        ASSERT_LE(angle_between(q, frame_of(wxyz, i)), error_max_rad) << "frame " << i;
        ASSERT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-12);
        ASSERT_EQ(decoder.sample(i), q) << "frame " << i;
    }
}

RotationTrackDecoder round_trip(const Track& wxyz, double error_max_rad, size_t* size = nullptr) {
    const std::vector<uint8_t> bytes =
        encode_rotation_track(wxyz.data(), frames_of(wxyz), error_max_rad);
    expect_within_bound(bytes, wxyz, error_max_rad);
    // Sizes show up in the XML report (--gtest_output=xml) for tuning.
    ::testing::Test::RecordProperty(bound_key(error_max_rad), int(bytes.size()));
    if (size) *size = bytes.size();
    return RotationTrackDecoder(bytes);
}

TEST(RotationCodec, SteadySpinIsOneSegment) {
    const Track wxyz = spin(1200, {0.2, -1.0, 0.4}, 10.0, quat_from_euler_xyz({0.5, 0.1, -2.0}));
    for (double bound : kBounds) {
        size_t size = 0;
        EXPECT_EQ(round_trip(wxyz, bound, &size).segment_count(), 1u) << "bound " << bound;
        EXPECT_LT(size, 24u);
    }
}

TEST(RotationCodec, SpinningUpIsCoveredByFarLongerSegmentsThanStraightOnes) {
    // Angle a t^2 / 2 about a fixed axis: interpolating it linearly over T seconds misses by up to
    // a T^2 / 8, so straight segments span at most sqrt(8 e / a); curved ones must cover several
    // times that (a constant angular acceleration is exactly what a bulge describes).
    const double acceleration_rad_s2 = 20;
    const Vec3 axis = unit({0.3, 1.0, -0.5});
    Track wxyz;
    for (uint32_t i = 0; i < 360; ++i) {
        const double t = i * kDt;
        push(wxyz, quat_from_axis_angle(axis, acceleration_rad_s2 * t * t / 2));
    }
    for (double bound : kBounds) {
        const double straight_frames = std::sqrt(8 * bound / acceleration_rad_s2) / kDt;
        const double straight_segments = (frames_of(wxyz) - 1) / std::max(1.0, straight_frames);
        EXPECT_LT(double(round_trip(wxyz, bound).segment_count()), straight_segments / 3) << "bound " << bound;
    }
}

TEST(RotationCodec, FastSpinBeyondHalfATurnPerFrameSegmentIsUnwrapped) {
    // 300 rad/s is 2.5 rad per frame: every segment turns many times round.
    const Track wxyz = spin(600, {1, 1, 0}, 300.0, {1, 0, 0, 0});
    for (double bound : kBounds) {
        EXPECT_LE(round_trip(wxyz, bound).segment_count(), 2u) << "bound " << bound;
    }
}

TEST(RotationCodec, TumblingStaysWithinBound) {
    const Track wxyz = tumbling(1200);
    for (double bound : kBounds) {
        const RotationTrackDecoder decoder = round_trip(wxyz, bound);
        // Piecewise-linear segments must cover many frames each on smooth motion.
        EXPECT_LT(decoder.segment_count(), 1200u / 4) << "bound " << bound;
    }
}

TEST(RotationCodec, RandomOrientationsStayWithinBound) {
    const Track wxyz = random_orientations(300, 3);
    for (double bound : kBounds) round_trip(wxyz, bound);
}

TEST(RotationCodec, JumpsStayWithinBound) {
    const Track wxyz = jumps(1200);
    for (double bound : kBounds) round_trip(wxyz, bound);
}

TEST(RotationCodec, RestingBodyCostsAFewBytes) {
    const Track wxyz = rest(1200, quat_from_euler_xyz({0.4, -1.2, 2.9}));
    for (double bound : kBounds) {
        size_t size = 0;
        EXPECT_EQ(round_trip(wxyz, bound, &size).segment_count(), 1u);
        EXPECT_LT(size, 16u) << "bound " << bound;
    }
}

TEST(RotationCodec, SignFlipsInTheInputChangeNothing) {
    const Track wxyz = tumbling(600);
    Track flipped = wxyz;
    for (size_t i = 0; i < flipped.size(); ++i) {
        if ((i / 4) % 3 == 1) flipped[i] = -flipped[i];
    }
    const double bound = 0.5 * kDegree;
    const std::vector<uint8_t> plain = encode_rotation_track(wxyz.data(), frames_of(wxyz), bound);
    const std::vector<uint8_t> signs = encode_rotation_track(flipped.data(), frames_of(wxyz), bound);
    expect_within_bound(signs, flipped, bound);
    EXPECT_EQ(RotationTrackDecoder(signs).segment_count(), RotationTrackDecoder(plain).segment_count());
}

TEST(RotationCodec, UnnormalizedInputIsNormalizedFirst) {
    Track wxyz = spin(240, {0, 0, 1}, 3.0, {1, 0, 0, 0});
    for (double& value : wxyz) value *= 3.7;
    round_trip(wxyz, 0.5 * kDegree);
}

TEST(RotationCodec, TinyBoundFallsBackToExactEscapes) {
    // Steps of 2^-46 rad cannot reach a turn of several radians per frame within the step limit.
    const Track wxyz = random_orientations(40, 9);
    round_trip(wxyz, 1e-13);
}

TEST(RotationCodec, ShortTracks) {
    for (uint32_t frames : {0u, 1u, 2u, 3u}) {
        const Track wxyz = spin(frames, {0, 1, 0}, 2.0, quat_from_euler_xyz({1, 2, 3}));
        const RotationTrackDecoder decoder = round_trip(wxyz, 0.5 * kDegree);
        EXPECT_EQ(decoder.frame_count(), frames);
        EXPECT_THROW(decoder.sample(frames), std::out_of_range);
    }
}

TEST(RotationCodec, RejectsInvalidInput) {
    Track wxyz = rest(5, {1, 0, 0, 0});
    EXPECT_THROW(encode_rotation_track(wxyz.data(), 5, 0.0), std::invalid_argument);
    EXPECT_THROW(encode_rotation_track(wxyz.data(), 5, -1.0), std::invalid_argument);
    EXPECT_THROW(encode_rotation_track(nullptr, 5, 0.01), std::invalid_argument);
    wxyz[8] = 0;
    EXPECT_THROW(encode_rotation_track(wxyz.data(), 5, 0.01), std::invalid_argument);
    wxyz[8] = NAN;
    EXPECT_THROW(encode_rotation_track(wxyz.data(), 5, 0.01), std::invalid_argument);
}

TEST(RotationCodec, RejectsOtherTrackKinds) {
    const Track wxyz = rest(5, {1, 0, 0, 0});
    std::vector<uint8_t> bytes = encode_rotation_track(wxyz.data(), 5, 0.01);
    bytes[0] = kPositionTrackFormatV1;
    EXPECT_THROW(RotationTrackDecoder{bytes}, CodecError);
}

TEST(RotationCodec, EveryTruncationThrows) {
    const Track wxyz = tumbling(600);
    const std::vector<uint8_t> bytes = encode_rotation_track(wxyz.data(), 600, 0.5 * kDegree);
    for (size_t size = 0; size < bytes.size(); ++size) {
        EXPECT_THROW(RotationTrackDecoder(bytes.data(), size), CodecError) << "size " << size;
    }
}

// Decodes possibly corrupted bytes: either CodecError, or unit quaternions (never a crash).
void expect_safe_decode(const std::vector<uint8_t>& bytes, uint32_t original_frames) {
    try {
        const RotationTrackDecoder decoder(bytes);
        if (decoder.frame_count() > 4 * original_frames + 16) return;
        Track decoded(4 * size_t{decoder.frame_count()});
        decoder.decode_all(decoded.data());
        for (uint32_t i = 0; i < decoder.frame_count(); ++i) {
            const Quat q = frame_of(decoded, i);
            ASSERT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-6);
        }
    } catch (const CodecError&) {
    }
}

TEST(RotationCodec, BitFlipsNeverCrash) {
    const Track wxyz = tumbling(600);
    const std::vector<uint8_t> bytes = encode_rotation_track(wxyz.data(), 600, 0.5 * kDegree);
    for (size_t bit = 0; bit < 8 * bytes.size(); ++bit) {
        std::vector<uint8_t> flipped = bytes;
        flipped[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
        expect_safe_decode(flipped, 600);
    }
}

TEST(RotationCodec, RandomBytesNeverCrash) {
    std::mt19937_64 random(78);
    for (int trial = 0; trial < 2000; ++trial) {
        std::vector<uint8_t> bytes(1 + random() % 48);
        for (uint8_t& b : bytes) b = static_cast<uint8_t>(random());
        // A valid tag (of either format) gets the parser past the first check.
        bytes[0] = trial % 2 ? kRotationTrackFormatV1 : kRotationTrackFormatV2;
        expect_safe_decode(bytes, 1000);
    }
}

}  // namespace
}  // namespace mwb
