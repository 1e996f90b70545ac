#include <gtest/gtest.h>

#include <map>
#include <set>

#include "SceneFixtures.h"
#include "sampler/Sampler.h"
#include "sim/CompiledScene.h"
#include "sim/SharedPrefix.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

constexpr uint64_t kSeed = 77;

// Twelve boxes, a hinged pair and a ball dropped from 3 m with no variation at all: every world
// falls the same way for about 0.8 s, then the perturbed impacts set them apart.
Scene dropped_pile() {
    Scene s = fixtures::pile(12, 72);
    s.name = "dropped_pile";
    for (Body& b : s.bodies) {
        b.variation = VariationRanges{};
        if (b.type == BodyType::Active) b.initial.location[2] += 3.0;
    }
    s.bodies.push_back(fixtures::sphere("Ball", {0.3, 0.2, 4.5}, 0.15));
    s.bodies.push_back(fixtures::box("LinkA", {-0.6, 0.9, 3.9}));
    s.bodies.push_back(fixtures::box("LinkB", {-0.2, 0.9, 3.9}));
    s.constraints.push_back(fixtures::hinge("Hinge", "LinkA", "LinkB", {-0.4, 0.9, 3.9}));
    return s;
}

std::map<uint64_t, uint64_t> reference_hashes(const CompiledScene& compiled, uint64_t count) {
    std::map<uint64_t, uint64_t> hashes;
    for (uint64_t k = 0; k < count; ++k) hashes[k] = hash_world(simulate_world(compiled, kSeed, k));
    return hashes;
}

TEST(SharedPrefix, WorldsThatStartAlikeComeOutAsIfSimulatedAlone) {
    const CompiledScene compiled(dropped_pile(), SimulationParameters{});
    ASSERT_TRUE(worlds_start_alike(compiled));
    const auto reference = reference_hashes(compiled, 6);
    PrefixSharingSimulator simulator(compiled, kSeed, true);
    std::set<uint64_t> distinct;
    for (uint64_t k = 0; k < 6; ++k) {
        const WorldResult world = simulator.simulate(k);
        ASSERT_EQ(world.status, WorldStatus::Ok) << world.reject_reason;
        EXPECT_EQ(world.first_frame, 0u);
        EXPECT_EQ(hash_world(world), reference.at(k)) << "world " << k;
        distinct.insert(hash_world(world));
        // From the second world on, the fall before the first impact (0.8 s) is not simulated
        // again: worlds start from the checkpoint at 0.5 s.
        EXPECT_EQ(simulator.shared_steps(), compiled.steps_per_checkpoint()) << "after world " << k;
    }
    EXPECT_EQ(distinct.size(), 6u) << "the perturbations still set every world apart";
}

TEST(SharedPrefix, SamplerGivesTheSameWorldsOnAnyThreadCountAndShard) {
    const CompiledScene compiled(dropped_pile(), SimulationParameters{});
    const auto reference = reference_hashes(compiled, 8);
    for (int threads : {1, 2}) {
        std::map<uint64_t, uint64_t> shared;
        sample_worlds(compiled, kSeed, 0, 8, threads, [&](WorldResult&& w) { shared[w.world_index] = hash_world(w); });
        EXPECT_EQ(shared, reference) << threads << " threads";
    }
    std::map<uint64_t, uint64_t> shard;
    sample_world_list(compiled, kSeed, {6, 3, 7}, 1, [&](WorldResult&& w) { shard[w.world_index] = hash_world(w); });
    EXPECT_EQ(shard, (std::map<uint64_t, uint64_t>{{3, reference.at(3)}, {6, reference.at(6)}, {7, reference.at(7)}}));
}

TEST(SharedPrefix, NothingIsSharedWhenInitialStatesVaryOrSharingIsOff) {
    const CompiledScene varied(fixtures::pile(12, 36), SimulationParameters{});
    EXPECT_FALSE(worlds_start_alike(varied));
    PrefixSharingSimulator on_varied(varied, kSeed, true);
    on_varied.simulate(0);
    on_varied.simulate(1);
    EXPECT_EQ(on_varied.shared_steps(), 0u);

    const CompiledScene alike(dropped_pile(), SimulationParameters{});
    PrefixSharingSimulator off(alike, kSeed, false);
    off.simulate(0);
    EXPECT_EQ(hash_world(off.simulate(1)), hash_world(simulate_world(alike, kSeed, 1)));
    EXPECT_EQ(off.shared_steps(), 0u);
}

TEST(SharedPrefix, AVariationRangeOfOneValueStillStartsWorldsAlike) {
    Scene scene = dropped_pile();
    // A range of one value moves the body, the same way in every world.
    scene.bodies.back().variation.location_min_m = {0.1, 0, 0};
    scene.bodies.back().variation.location_max_m = {0.1, 0, 0};
    EXPECT_TRUE(worlds_start_alike(CompiledScene(scene, SimulationParameters{})));
    scene.bodies.back().variation.mass_scale_max = 1.01;
    EXPECT_FALSE(worlds_start_alike(CompiledScene(scene, SimulationParameters{})));
}

}  // namespace
}  // namespace mwb
