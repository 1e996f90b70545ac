#include <gtest/gtest.h>

#include <map>
#include <set>
#include <mutex>

#include "SceneFixtures.h"
#include "sampler/Sampler.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

std::map<uint64_t, uint64_t> hashes_with_threads(const CompiledScene& compiled, uint64_t count, int threads) {
    std::map<uint64_t, uint64_t> hashes;
    const SamplingStatistics stats = sample_worlds(compiled, 2024, 0, count, threads,
                                                   [&](WorldResult&& w) { hashes[w.world_index] = hash_world(w); });
    EXPECT_EQ(stats.worlds_ok, count);
    return hashes;
}

std::map<uint64_t, uint64_t> hashes_in_reverse(const CompiledScene& compiled, uint64_t count) {
    std::map<uint64_t, uint64_t> hashes;
    for (uint64_t k = count; k-- > 0;) hashes[k] = hash_world(simulate_world(compiled, 2024, k));
    return hashes;
}

class Determinism : public ::testing::TestWithParam<const char*> {
protected:
    Scene scene() const {
        return std::string(GetParam()) == "pile" ? fixtures::pile(24, 36) : fixtures::mesh_ramp_with_joints();
    }
};

TEST_P(Determinism, SameWorldsOnOneAndTwoThreadsAndInAnyOrder) {
    CompiledScene compiled(scene(), SimulationParameters{});
    const uint64_t count = 8;
    const auto one = hashes_with_threads(compiled, count, 1);
    const auto two = hashes_with_threads(compiled, count, 2);
    const auto reversed = hashes_in_reverse(compiled, count);
    EXPECT_EQ(one, two);
    EXPECT_EQ(one, reversed);
    std::set<uint64_t> distinct;
    for (const auto& [index, hash] : one) distinct.insert(hash);
    EXPECT_EQ(distinct.size(), count) << "every world differs";
}

INSTANTIATE_TEST_SUITE_P(Scenes, Determinism, ::testing::Values("pile", "mesh_ramp"));

TEST(Determinism, CancelKeepsFinishedWorldsIntact) {
    CompiledScene compiled(fixtures::pile(8, 24), SimulationParameters{});
    SamplingProgress progress;
    std::vector<WorldResult> delivered;
    sample_worlds(compiled, 5, 0, 40, 2, [&](WorldResult&& w) {
        delivered.push_back(std::move(w));
        if (delivered.size() == 3) progress.cancel = true;
    }, &progress);
    EXPECT_LT(delivered.size(), 40u);
    for (const WorldResult& w : delivered) {
        if (w.status != WorldStatus::Ok) continue;
        EXPECT_EQ(hash_world(w), hash_world(simulate_world(compiled, 5, w.world_index)));
    }
}

}  // namespace
}  // namespace mwb
