#include <gtest/gtest.h>

#include <map>

#include "SceneFixtures.h"
#include "WorldCompare.h"
#include "sampler/Sampler.h"
#include "sim/CompiledScene.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

using compare::position;
using compare::same_track;

// Boxes tumbling down onto each other: lots of collisions, so refinements really diverge.
Scene busy_scene() {
    Scene s = fixtures::pile(12, 72);
    for (Body& b : s.bodies) b.restitution = 0.3;
    return s;
}

SimulationParameters strong_perturbation() {
    SimulationParameters p;
    p.alpha_linear = p.alpha_angular = 0.4;
    p.stop_at_rest = false;  // the branches below are late in the world
    return p;
}

TEST(Refine, ChildrenEqualTheirParentBeforeTheBranchAndWhereverUntouched) {
    CompiledScene compiled(busy_scene(), strong_perturbation());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 3, 0, {});
    const WorldResult& parent = chain.back();
    const uint32_t branch_frame = 96;  // 0.8 s: between two checkpoints, while the pile still moves
    const uint32_t chosen = 9;
    std::vector<RefineStep> children;
    for (uint64_t k = 0; k < 6; ++k) children.push_back({branch_frame * compiled.steps_per_frame(), 100 + k, {chosen}});
    std::map<uint64_t, WorldResult> refined;
    refine_worlds(compiled, 3, chain, children, 2, [&](WorldResult&& w) { refined.emplace(w.world_index, std::move(w)); });
    ASSERT_EQ(refined.size(), 6u);
    size_t diverged = 0;
    for (const auto& [index, child] : refined) {
        ASSERT_EQ(child.status, WorldStatus::Ok) << child.reject_reason;
        ASSERT_EQ(child.lineage.size(), 1u);
        EXPECT_EQ(child.changed[chosen], 1);
        for (uint32_t b = 0; b < child.body_count; ++b) {
            EXPECT_TRUE(same_track(child, parent, b, branch_frame + 1)) << "body " << b << " before the branch";
            if (!child.changed[b]) {
                EXPECT_TRUE(same_track(child, parent, b, std::min(child.frame_count, parent.frame_count)))
                    << "untouched body " << b << " of world " << index;
            }
        }
        diverged += !same_track(child, parent, chosen, std::min(child.frame_count, parent.frame_count));
    }
    EXPECT_GE(diverged, 4u) << "new perturbations give new motion";
}

TEST(Refine, AChildIsReproducedExactlyFromItsLineageOnAnyThreadCount) {
    CompiledScene compiled(busy_scene(), strong_perturbation());
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 3, 1, {});
    std::vector<RefineStep> children;
    for (uint64_t k = 0; k < 4; ++k) children.push_back({96 * compiled.steps_per_frame(), 200 + k, {7, 8}});
    std::map<uint64_t, uint64_t> one, two;
    refine_worlds(compiled, 3, chain, children, 1, [&](WorldResult&& w) { one[w.world_index] = hash_world(w); });
    refine_worlds(compiled, 3, chain, children, 2, [&](WorldResult&& w) { two[w.world_index] = hash_world(w); });
    EXPECT_EQ(one, two);
    const std::vector<WorldResult> again = simulate_lineage(compiled, 3, 1, {children[2]});
    EXPECT_EQ(hash_world(again.back()), one[202]);
}

TEST(Refine, RefiningARefinedWorldKeepsItsPastAndCanGoBackInTime) {
    CompiledScene compiled(busy_scene(), strong_perturbation());
    const uint32_t spf = compiled.steps_per_frame();
    std::vector<WorldResult> chain = simulate_lineage(compiled, 3, 2, {{60 * spf, 300, {5}}});
    // A grandchild branching later keeps the child's motion up to its branch...
    const WorldResult later = refine_world(compiled, 3, chain, {180 * spf, 301, {6}});
    for (uint32_t b = 0; b < later.body_count; ++b) EXPECT_TRUE(same_track(later, chain.back(), b, 181)) << b;
    // ... and one branching earlier than the child did is the child's motion up to that time.
    const WorldResult earlier = refine_world(compiled, 3, chain, {30 * spf, 302, {6}});
    for (uint32_t b = 0; b < earlier.body_count; ++b) EXPECT_TRUE(same_track(earlier, chain.back(), b, 31)) << b;
    chain.push_back(later);
    EXPECT_EQ(hash_world(simulate_lineage(compiled, 3, 2, later.lineage).back()), hash_world(later));
}

// A rolling ball A aimed at box D; box B beside the start and box C far away. The parent's record
// of A is edited to run into B instead: refining A then shows both rules. A's new (real) motion
// hits D, so D is simulated; A's ghost follows the recorded path into B, so B is simulated too
// (in the parent A touched it; now it may not). C, touched by neither, replays bit for bit.
TEST(Refine, BodiesHitNowOrHitBeforeAreSimulatedAndOthersReplay) {
    Scene scene;
    scene.world.frame_end = 49;
    scene.bodies.push_back(fixtures::ground());
    Body ball = fixtures::sphere("A", {0, 0, 0.3}, 0.3);
    ball.initial_linear_velocity = {3, 0, 0};
    ball.initial_angular_velocity = {0, 10, 0};
    scene.bodies.push_back(ball);
    scene.bodies.push_back(fixtures::box("B", {0, 1.5, 0.2}));
    scene.bodies.push_back(fixtures::box("C", {8, 8, 0.2}));
    scene.bodies.push_back(fixtures::box("D", {2, 0, 0.2}));
    SimulationParameters p;
    p.stop_at_rest = false;
    CompiledScene compiled(scene, p);
    std::vector<WorldResult> chain = simulate_lineage(compiled, 1, 0, {});
    WorldResult& parent = chain.back();
    ASSERT_GT(norm(sub(position(parent, 4, parent.frame_count - 1), {2, 0, 0.2})), 0.1) << "A pushes D in reality";
    for (uint32_t f = 0; f < parent.frame_count; ++f) {  // the record says: A rolled into B
        const double u = std::min(1.0, f / 120.0);
        parent.positions_m[(1 * parent.frame_count + f) * 3 + 0] = 0;
        parent.positions_m[(1 * parent.frame_count + f) * 3 + 1] = 1.5 * u;
    }
    const WorldResult child = refine_world(compiled, 1, chain, {0, 50, {1}});
    ASSERT_EQ(child.status, WorldStatus::Ok);
    EXPECT_EQ(child.changed[1], 1) << "A";
    EXPECT_EQ(child.changed[4], 1) << "D is hit by A's new motion";
    EXPECT_EQ(child.changed[2], 1) << "B was hit in the parent: its ghost finds it";
    EXPECT_EQ(child.changed[3], 0) << "C";
    EXPECT_TRUE(same_track(child, parent, 3, child.frame_count));
    EXPECT_GT(norm(sub(position(child, 4, child.frame_count - 1), {2, 0, 0.2})), 0.1) << "D really moves";
    EXPECT_LT(norm(sub(position(child, 2, child.frame_count - 1), {0, 1.5, 0.2})), 0.01) << "B stays put now";
}

TEST(Refine, BadRequestsAreRefusedBeforeAnyWork) {
    CompiledScene compiled(fixtures::ball_on_plane(), SimulationParameters{});
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 1, 0, {});
    EXPECT_THROW(refine_world(compiled, 1, chain, {1, 9, {1}}), std::invalid_argument);        // not a frame
    EXPECT_THROW(refine_world(compiled, 1, chain, {0, 9, {0}}), std::invalid_argument);        // the ground
    EXPECT_THROW(refine_world(compiled, 1, chain, {0, 9, {}}), std::invalid_argument);
    EXPECT_THROW(refine_world(compiled, 1, chain, {2 * 100000, 9, {1}}), std::invalid_argument);  // after its end
    EXPECT_THROW(refine_worlds(compiled, 1, chain, {{0, 9, {7}}}, 2, [](WorldResult&&) {}), std::invalid_argument);
}

}  // namespace
}  // namespace mwb
