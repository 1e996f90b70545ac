#include <gtest/gtest.h>

#include "SceneFixtures.h"
#include "refine/LineageCache.h"
#include "refine/WorldMaker.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

// Boxes tumbling onto each other, refined twice: a lineage of three worlds.
struct TwiceRefined : ::testing::Test {
    static SimulationParameters parameters() {
        SimulationParameters p;
        p.alpha_linear = p.alpha_angular = 0.4;
        p.stop_at_rest = false;
        return p;
    }
    CompiledScene compiled{fixtures::pile(12, 72), parameters()};
    uint32_t spf = compiled.steps_per_frame();
    std::vector<RefineStep> lineage{{60 * spf, 300, {5}}, {120 * spf, 301, {6}}};
    std::vector<WorldResult> full = simulate_lineage(compiled, 3, 0, lineage);

    RefinementJob job_for_the_last() const {
        RefinementJob job;
        job.parent_world = 301;
        job.root_world = 0;
        job.lineage = lineage;
        job.parent_frames = full.back().frame_count;
        job.parent_contacts = full.back().contacts.size();
        job.library_build = "many-worlds 0.0.9; another build";
        return job;
    }
};

TEST_F(TwiceRefined, ALineageKeptInPartIsFinishedBySimulatingTheRestBitForBit) {
    LineageCache cache(size_t{1} << 30);
    cache.keep(full[0]);
    cache.keep(full[1]);
    const std::vector<WorldResult> chain = exact_lineage(compiled, 3, job_for_the_last(), &cache);
    ASSERT_EQ(chain.size(), 3u);
    for (size_t k = 0; k < chain.size(); ++k) EXPECT_EQ(hash_world(chain[k]), hash_world(full[k])) << k;
    EXPECT_EQ(cache.kept_start(0, lineage).size(), 3u) << "the world it simulated is kept for the next time";
}

TEST_F(TwiceRefined, OnlyTheUnbrokenStartOfALineageIsTakenFromTheCache) {
    LineageCache cache(size_t{1} << 30);
    cache.keep(full[0]);
    cache.keep(full[2]);  // the middle world is not kept
    EXPECT_EQ(cache.kept_start(0, lineage).size(), 1u);
    EXPECT_TRUE(LineageCache(size_t{1} << 30).kept_start(0, lineage).empty());
}

TEST_F(TwiceRefined, AWorldKeptWithoutACopyComesBackTheSameAndCountsTheRoomItHolds) {
    // A worker keeps each world it made by moving it in: it must come back bit for bit, and the
    // memory bound must count what the world holds, its vectors' spare room too.
    WorldResult moved = full[0];
    const size_t used = moved.positions_m.size() * sizeof(double);
    moved.positions_m.reserve(moved.positions_m.size() * 4);
    LineageCache roomy(size_t{1} << 30);
    roomy.keep(WorldResult(full[0]));
    ASSERT_EQ(roomy.kept_start(0, {}).size(), 1u);
    EXPECT_EQ(hash_world(roomy.kept_start(0, {}).front()), hash_world(full[0]));
    // A bound the used positions fit three times over, but not the room reserved for four times.
    LineageCache tight(roomy.bytes() + 2 * used);
    tight.keep(std::move(moved));
    EXPECT_TRUE(tight.kept_start(0, {}).empty()) << "the spare room counts against the bound";
    EXPECT_EQ(tight.bytes(), 0u);
}

TEST_F(TwiceRefined, AParentThatDoesNotComeOutAsStoredIsRefusedNamingBothBuilds) {
    RefinementJob job = job_for_the_last();
    job.parent_contacts += 1;  // what another build's world would have stored
    try {
        exact_lineage(compiled, 3, job, nullptr);
        FAIL() << "a world that does not reproduce must be refused";
    } catch (const WorldNotReproduced& error) {
        const std::string message = error.what();
        EXPECT_NE(message.find("world 301 does not come out as stored"), std::string::npos) << message;
        EXPECT_NE(message.find("another build"), std::string::npos) << message;
    }
    // The same stored record, re-simulated under another seed, does not reproduce either.
    EXPECT_THROW(exact_lineage(compiled, 4, job_for_the_last(), nullptr), WorldNotReproduced);
}

}  // namespace
}  // namespace mwb
