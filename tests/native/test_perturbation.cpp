#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "SceneFixtures.h"
#include "sim/CompiledScene.h"
#include "sim/ImpactPerturber.h"
#include "sim/PortableRandom.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

TEST(ImpactPerturber, MagnitudeNeverExceedsAlphaTimesTheVelocityJump) {
    const ImpactPerturber perturber(0.1, 50);
    PortableRandom random(42);
    double largest_ratio = 0;
    for (int i = 0; i < 100000; ++i) {
        const Vec3 delta{random.uniform(-5, 5), random.uniform(-5, 5), random.uniform(-5, 5)};
        const double ratio = norm(perturber.perturbation(delta, random)) / norm(delta);
        ASSERT_LE(ratio, 0.1 * (1 + 1e-12));
        largest_ratio = std::max(largest_ratio, ratio);
    }
    EXPECT_GT(largest_ratio, 0.099) << "the whole ±alpha range is used";
}

TEST(ImpactPerturber, DirectionsFollowTheCosineLobe) {
    // For p(θ) ∝ cos^n θ sin θ, cos θ has density (n+1) c^n on [0, 1]: E[c] = (n+1)/(n+2),
    // E[c^2] = (n+1)/(n+3).
    for (double n : {1.0, 50.0}) {
        const ImpactPerturber perturber(0.1, n);
        PortableRandom random(7);
        const Vec3 axis = scale(Vec3{1, 2, -2}, 1.0 / 3.0);
        const int samples = 200000;
        double sum = 0, sum_sq = 0;
        for (int i = 0; i < samples; ++i) {
            const Vec3 d = perturber.sample_lobe_direction(axis, random);
            ASSERT_NEAR(norm(d), 1.0, 1e-12);
            const double c = dot(d, axis);
            ASSERT_GE(c, 0.0);
            sum += c;
            sum_sq += c * c;
        }
        const double mean = sum / samples;
        const double expected = (n + 1) / (n + 2);
        const double sd = std::sqrt((n + 1) / (n + 3) - expected * expected);
        EXPECT_NEAR(mean, expected, 5 * sd / std::sqrt(samples)) << "n = " << n;
    }
}

TEST(ImpactPerturber, AzimuthIsUniformAroundTheAxis) {
    const ImpactPerturber perturber(0.1, 1);
    PortableRandom random(9);
    int quadrant[4] = {0, 0, 0, 0};
    const int samples = 40000;
    for (int i = 0; i < samples; ++i) {
        const Vec3 d = perturber.sample_lobe_direction({0, 0, 1}, random);
        quadrant[(d[0] >= 0 ? 0 : 1) + (d[1] >= 0 ? 0 : 2)]++;
    }
    for (int q : quadrant) EXPECT_NEAR(q, samples / 4, 5 * std::sqrt(samples * 0.25 * 0.75));
}

TEST(Perturbation, WorldsDifferOnlyThroughPerturbationWhenNothingIsRandomized) {
    Scene scene = fixtures::pile(6, 48);
    for (Body& b : scene.bodies) b.variation = VariationRanges{};
    SimulationParameters off;
    off.perturb = false;
    CompiledScene unperturbed(scene, off);
    const WorldResult first = simulate_world(unperturbed, 1, 0);
    const WorldResult other = simulate_world(unperturbed, 1, 5);
    EXPECT_EQ(first.positions_m, other.positions_m);
    EXPECT_EQ(first.orientations, other.orientations);
    CompiledScene perturbed(scene, SimulationParameters{});
    const WorldResult a = simulate_world(perturbed, 1, 0);
    const WorldResult b = simulate_world(perturbed, 1, 5);
    EXPECT_GT(a.impacts_perturbed, 0u);
    EXPECT_NE(hash_world(a), hash_world(b));
}

TEST(PortableRandom, UniformStaysInRangeAndCoversIt) {
    PortableRandom random(123);
    double lo = 1, hi = 0;
    for (int i = 0; i < 100000; ++i) {
        const double u = random.uniform01();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        lo = std::min(lo, u);
        hi = std::max(hi, u);
    }
    EXPECT_LT(lo, 1e-3);
    EXPECT_GT(hi, 1 - 1e-3);
}

TEST(PortableRandom, WorldSeedsAreDistinctAcrossIndicesAndBaseSeeds) {
    std::vector<uint64_t> seeds;
    for (uint64_t base = 0; base < 4; ++base)
        for (uint64_t index = 0; index < 1000; ++index) seeds.push_back(derive_world_seed(base, index));
    std::sort(seeds.begin(), seeds.end());
    EXPECT_EQ(std::unique(seeds.begin(), seeds.end()), seeds.end());
}

}  // namespace
}  // namespace mwb
