// Where a goal search branches a world, on a hand-made world of three boxes on a floor: it never
// re-simulates a body holding a met part, re-simulates a touch of one only once nothing else is
// left, never branches where nothing after would be perturbed, and turns to the next part a world
// misses when one keeps failing.
#include <gtest/gtest.h>

#include <set>

#include "SceneFixtures.h"
#include "seek/BranchPlanner.h"

namespace mwb {
namespace {

constexpr double kHz = 120;

// Floor 0; boxes A 1, B 2, C 3; a goal part per box.
struct ThreeBoxes {
    Scene scene;
    std::vector<QueryBox> parts;
    StoredWorld world;
    GoalScore score;

    ThreeBoxes() {
        scene.bodies = {fixtures::ground(), fixtures::box("A", {-1, 0, 0.2}), fixtures::box("B", {0, 0, 0.2}),
                        fixtures::box("C", {1, 0, 0.2})};
        for (uint32_t body : {1u, 2u, 3u}) {
            QueryBox part;
            part.bodies = {body};
            part.window = {9.0, 10.0};
            parts.push_back(part);
        }
        world.record_hz = kHz;
        world.frame_count = 1201;  // 10 s
        // B hits the floor at 1, 2, 3, 5 and 5.5 s and A (in its box) at 4 s; C the floor at
        // 0.5, 1.5 and 2.5 s, then nothing.
        for (double t : {1.0, 2.0, 3.0, 5.0, 5.5}) world.contacts.push_back({t, 2, 0, 1.0});
        world.contacts.push_back({4.0, 2, 1, 1.0});
        for (double t : {0.5, 1.5, 2.5}) world.contacts.push_back({t, 3, 0, 1.0});
        // A meets its part; B misses its part by less than C does; both went wrong at 6 s.
        score.boxes_met = 1;
        score.met = {1, 0, 0};
        score.met_time_s = {8.0, 0, 0};
        score.misses = {{1, 0.6, 6.0, 0.0, {2}}, {2, 0.3, 6.0, 0.0, {3}}};
        score.first_unmet = 1;
        score.closeness = 0.6;
        score.failure_time_s = 6.0;
        score.failing_bodies = {2};
    }
};

double seconds(const Branch& b) { return static_cast<double>(b.frame) / kHz; }

TEST(BranchPlanner, KeepsMetPartsBranchesOnlyWhereSomethingIsPerturbedAndTriesEveryPartOnce) {
    const ThreeBoxes s;
    BranchPlanner planner(s.scene, s.parts, 7);
    std::vector<Branch> chosen;
    Branch b;
    while (planner.choose(0, s.world, s.score, b)) {
        ASSERT_EQ(b.bodies.size(), 1u) << "A, which holds its part, is never re-simulated";
        chosen.push_back(b);
        ASSERT_LT(chosen.size(), 50u);
    }
    // First every point that keeps A's part: B only after its touch of A at 4 s, at its impacts
    // after it; C only up to its last impact (the 0.5 s grid and its impacts).
    ASSERT_EQ(chosen.size(), 12u);
    size_t of_b = 0, of_c = 0;
    for (size_t k = 0; k < 8; ++k) {
        const Branch& p = chosen[k];
        if (p.bodies[0] == 2) {
            ++of_b;
            EXPECT_GT(seconds(p), 4.0) << "B before its touch of A would put A's part at risk";
        } else {
            ++of_c;
            EXPECT_EQ(p.bodies, (std::vector<uint32_t>{3}));
            EXPECT_LE(seconds(p), 2.5) << "nothing of C is perturbed after 2.5 s";
        }
    }
    EXPECT_EQ(of_b, 2u);
    EXPECT_EQ(of_c, 6u);  // 0, 0.5, 1.0, 1.5, 2.0, 2.5 s
    // Only then, with nothing else left, B at its impacts up to and at its touch of A.
    for (size_t k = 8; k < chosen.size(); ++k) {
        EXPECT_EQ(chosen[k].bodies, (std::vector<uint32_t>{2}));
        EXPECT_LE(seconds(chosen[k]), 4.0);
    }
    std::set<std::pair<uint32_t, uint64_t>> distinct;
    for (const Branch& p : chosen) distinct.insert({p.bodies[0], p.frame});
    EXPECT_EQ(distinct.size(), chosen.size()) << "each point once";
}

TEST(BranchPlanner, APartWhoseChildrenFailGivesWayToTheNextOne) {
    const ThreeBoxes s;
    BranchPlanner planner(s.scene, s.parts, 7);
    Branch first, second, third;
    ASSERT_TRUE(planner.choose(0, s.world, s.score, first));
    EXPECT_EQ(first.bodies, (std::vector<uint32_t>{2})) << "the nearest part first";
    // Its children came out no better: the next refinement works on C's part.
    planner.note_children(0, 1.6, {{10, 1.55}, {11, 1.4}}, 0.02);
    ASSERT_TRUE(planner.choose(0, s.world, s.score, second));
    EXPECT_EQ(second.bodies, (std::vector<uint32_t>{3}));
    // A child better than its parent on C's part: B's part (one failure) and C's (none) again in
    // order of their failures, C's first.
    planner.note_children(0, 1.6, {{12, 1.9}}, 0.02);
    ASSERT_TRUE(planner.choose(0, s.world, s.score, third));
    EXPECT_EQ(third.bodies, (std::vector<uint32_t>{3}));
}

}  // namespace
}  // namespace mwb
