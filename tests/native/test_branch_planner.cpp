// Where a goal search branches a world, on a hand-made world of three boxes on a floor: it never
// re-simulates a body holding a met part; it branches where the refined bodies' touches, or the
// touches those pass on, reach a met body only once nothing else is left; it never branches where
// nothing after would be perturbed, turns to the next part a world misses when one keeps
// failing, and learns how late in a part's span to branch from which refinements paid.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <set>
#include <utility>
#include <vector>

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

TEST(BranchPlanner, ATouchPassedOnToAMetBodyPutsItAtRiskToo) {
    // C hits B at 2 s and B hits A (in its box) at 4 s: a child whose C goes another way may
    // leave B on another course too, into A. C is the only part left.
    ThreeBoxes s;
    s.world.contacts.push_back({2.0, 3, 2, 1.0});
    s.score.misses = {{2, 0.3, 6.0, 0.0, {3}}};
    s.score.first_unmet = 2;
    s.score.failing_bodies = {3};
    BranchPlanner planner(s.scene, s.parts, 7);
    std::vector<Branch> chosen;
    Branch b;
    while (planner.choose(0, s.world, s.score, b)) {
        chosen.push_back(b);
        ASSERT_LT(chosen.size(), 50u);
    }
    // Keeping A: C after its touch of B (its impact at 2.5 s), and C with B (which hit it) after
    // B's touch of A (B's impacts at 5 and 5.5 s).
    const std::set<std::pair<std::vector<uint32_t>, double>> keeping = {{{3}, 2.5}, {{2, 3}, 5.0}, {{2, 3}, 5.5}};
    ASSERT_EQ(chosen.size(), 10u);
    std::set<std::pair<std::vector<uint32_t>, double>> first;
    for (size_t k = 0; k < 3; ++k) first.insert({chosen[k].bodies, seconds(chosen[k])});
    EXPECT_EQ(first, keeping);
    // Then the rest: C alone at 0.5, 1.5 and 2 s, whose touch passes on to A, and C with B up to 4 s.
    for (size_t k = 3; k < chosen.size(); ++k) {
        EXPECT_LE(seconds(chosen[k]), chosen[k].bodies.size() == 1 ? 2.0 : 4.0);
    }
}

TEST(BranchPlanner, APosesPointsRiskingManyMetBodiesComeAfterThoseRiskingFew) {
    // A, B and C hold their parts; D misses its pose. D touches A at 2 s, B at 3 s and C at 4 s,
    // and hits the floor at 1, 2.5, 3.5, 4.5 and 5 s. A point before 2 s puts all three at risk.
    Scene scene;
    scene.bodies = {fixtures::ground(), fixtures::box("A", {-1, 0, 0.2}), fixtures::box("B", {0, 0, 0.2}),
                    fixtures::box("C", {1, 0, 0.2}), fixtures::box("D", {2, 0, 0.2})};
    std::vector<QueryBox> parts;
    for (uint32_t body : {1u, 2u, 3u, 4u}) {
        QueryBox part;
        part.bodies = {body};
        part.window = {9.0, 10.0};
        parts.push_back(part);
    }
    StoredWorld world;
    world.record_hz = kHz;
    world.frame_count = 1201;
    const std::vector<double> touches = {2.0, 3.0, 4.0};
    for (uint32_t k = 0; k < 3; ++k) world.contacts.push_back({touches[k], 4, static_cast<int32_t>(k + 1), 1.0});
    for (double t : {1.0, 2.5, 3.5, 4.5, 5.0}) world.contacts.push_back({t, 4, 0, 1.0});
    std::sort(world.contacts.begin(), world.contacts.end(),
              [](const ContactEvent& x, const ContactEvent& y) { return x.time_s < y.time_s; });
    GoalScore score;
    score.boxes_met = 3;
    score.met = {1, 1, 1, 0};
    score.met_time_s = {9.0, 9.0, 9.0, 0};
    score.misses = {{3, 0.5, 6.0, 0.0, {4}}};
    score.first_unmet = 3;
    score.closeness = 0.5;
    score.failure_time_s = 6.0;
    score.failing_bodies = {4};
    const auto risked = [&](const Branch& b) {
        return std::count_if(touches.begin(), touches.end(), [&](double t) { return t >= seconds(b) - 1e-9; });
    };
    // The order in which a planner offers its points, as the number of met bodies each risks.
    const auto offered = [&](const std::vector<QueryBox>& goal) {
        BranchPlanner planner(scene, goal, 7);
        std::vector<long> order;
        Branch b;
        while (planner.choose(0, world, score, b)) {
            order.push_back(static_cast<long>(risked(b)));
            if (order.size() > 100) break;
        }
        return order;
    };
    // As a box: every point keeping A, B and C first, then the rest in any order.
    const std::vector<long> as_box = offered(parts);
    // As a pose: those keeping them, then those risking one or two, then those risking all three.
    parts[3].orientation = OrientationTest{};
    const std::vector<long> as_pose = offered(parts);
    ASSERT_EQ(as_pose.size(), as_box.size()) << "a pose is offered the same points, in another order";
    const auto pass = [](long r) { return r == 0 ? 0 : r <= 2 ? 1 : 2; };
    for (size_t k = 1; k < as_pose.size(); ++k) EXPECT_LE(pass(as_pose[k - 1]), pass(as_pose[k])) << "point " << k;
    EXPECT_EQ(std::count(as_pose.begin(), as_pose.end(), 0), std::count(as_box.begin(), as_box.end(), 0));
    EXPECT_GT(std::count(as_pose.begin(), as_pose.end(), 3), 0);
    EXPECT_GT(std::count_if(as_pose.begin(), as_pose.end(), [](long r) { return r == 1 || r == 2; }), 0);
    // A box mixes the points risking three with those risking fewer.
    bool mixed = false;
    for (size_t k = 1; k < as_box.size(); ++k) mixed |= as_box[k - 1] == 3 && (as_box[k] == 1 || as_box[k] == 2);
    EXPECT_TRUE(mixed);
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

TEST(BranchPlanner, ABrokenWorldIsBranchedOnlyBeforeItBroke) {
    // C also has to keep out of a box (a fourth, negative part) and entered it at 3 s: nothing it
    // or B does after that counts, so B's points after its touch of A (5 and 5.5 s), which
    // the world unbroken is branched at first, and C's grid after 3 s are no use.
    ThreeBoxes s;
    QueryBox keep_out;
    keep_out.bodies = {3};
    keep_out.negative = true;
    s.parts.push_back(keep_out);
    s.score.met.push_back(0);
    s.score.met_time_s.push_back(0);
    s.score.misses.push_back({3, 0.1, 3.0, 0.0, {3}});
    s.score.violation_time_s = 3.0;
    BranchPlanner planner(s.scene, s.parts, 7);
    std::vector<Branch> chosen;
    Branch b;
    while (planner.choose(0, s.world, s.score, b)) {
        chosen.push_back(b);
        ASSERT_LT(chosen.size(), 50u);
    }
    ASSERT_FALSE(chosen.empty()) << "a broken world can still be mended before it broke";
    std::set<uint32_t> bodies;
    for (const Branch& p : chosen) {
        EXPECT_LT(seconds(p), 3.0) << "branched after the world broke, for body " << p.bodies[0];
        bodies.insert(p.bodies.begin(), p.bodies.end());
    }
    EXPECT_TRUE(bodies.count(3)) << "C, which broke it, is refined before it did";
}

// C alone misses its part (A meets its own); C hits the floor every 0.25 s until 6 s, when it
// went wrong: points all over its span. Each of `worlds` worlds (the same record) is refined
// once, and its children meet C's part only when it branched in the first quarter of that span
// (or, if `late_pays`, in the last). Returns the branch times chosen, in order.
std::vector<double> times_chosen_when_only_some_pay(bool late_pays, size_t worlds) {
    ThreeBoxes s;
    s.world.contacts.clear();
    for (double t = 0.25; t < 6.0; t += 0.25) s.world.contacts.push_back({t, 3, 0, 1.0});
    s.score.misses = {{2, 0.3, 6.0, 0.0, {3}}};
    s.score.first_unmet = 2;
    s.score.failing_bodies = {3};
    s.score.closeness = 0.3;
    BranchPlanner planner(s.scene, s.parts, 11);
    std::vector<double> times;
    for (uint64_t world = 0; world < worlds; ++world) {
        Branch b;
        EXPECT_TRUE(planner.choose(world, s.world, s.score, b));
        const double t = seconds(b);
        times.push_back(t);
        const bool pays = late_pays ? t >= 4.5 : t < 1.5;
        // A child meeting C's part has 2 parts met; one that does not comes no closer.
        planner.note_children(world, 1.3, {{1000 + world, pays ? 2.1 : 1.3}}, 0.02);
    }
    return times;
}

TEST(BranchPlanner, LearnsHowLateToBranchFromTheRefinementsThatPaid) {
    // A letter's fall through pegs is decided early: branched in the last half of it, no child
    // reached the letter's slot (SIGGRAPH), so a planner that always tried the latest points
    // first spent most of its search there. Split the span in quarters: once one has paid, the
    // planner branches mostly there, whichever it is.
    for (bool late_pays : {false, true}) {
        const std::vector<double> times = times_chosen_when_only_some_pay(late_pays, 60);
        size_t paying = 0;
        for (size_t k = 30; k < times.size(); ++k) paying += late_pays ? times[k] >= 4.5 : times[k] < 1.5;
        EXPECT_GE(paying, 25u) << (late_pays ? "the last" : "the first") << " quarter pays; of the last 30 choices, "
                               << paying << " were there";
    }
}

// C meets two parts in order (its first spot at 1 s, its second at 2 s) and then has to be at a
// third some time from 5 s to the world's end (10 s); it came nearest at `failure_time_s`, and
// was in it before 5 s at `early_visit_s` (infinity: never). Every branch point it is given, in
// the order they come.
std::vector<double> chain_points(double failure_time_s, double early_visit_s) {
    ThreeBoxes s;
    for (QueryBox& part : s.parts) part.bodies = {3};
    s.parts[0].window = s.parts[1].window = {};
    s.parts[2].window = {5.0, 10.0};
    s.parts[1].after = 0;
    s.parts[2].after = 1;
    s.world.contacts.clear();
    for (double t = 0.25; t < 9.5; t += 0.25) s.world.contacts.push_back({t, 3, 0, 1.0});
    s.score.boxes_met = 2;
    s.score.met = {1, 1, 0};
    s.score.met_time_s = {1.0, 2.0, 0};
    s.score.misses = {{2, 0.3, failure_time_s, 2.0, {3}, early_visit_s}};
    s.score.first_unmet = 2;
    s.score.closeness = 0.3;
    s.score.failure_time_s = failure_time_s;
    s.score.failing_bodies = {3};
    BranchPlanner planner(s.scene, s.parts, 7);
    std::vector<double> times;
    Branch b;
    while (planner.choose(0, s.world, s.score, b)) {
        times.push_back(seconds(b));
        if (times.size() > 100) break;
    }
    return times;
}

TEST(BranchPlanner, AWorldTooFastOrTooSlowForAnOrderedPartIsBranchedAllTheWayBack) {
    const double never = std::numeric_limits<double>::infinity();
    // Missed in place: C came nearest its third spot 6 s in, inside that part's window, or stopped
    // short of it at 3 s. Keeping what the parts before achieved, all but the last, it is branched
    // only after the first was met (1 s).
    for (double failure : {6.0, 3.0}) {
        const std::vector<double> in_place = chain_points(failure, never);
        ASSERT_FALSE(in_place.empty());
        EXPECT_GE(*std::min_element(in_place.begin(), in_place.end()), 1.0) << "came nearest at " << failure << " s";
    }
    // Too fast: C was in its third spot at 3 s, before the window opened, and went on (the
    // staircase's figure sliding off the bottom). Too slow: it was still on its way at the end
    // (the figure that rested on a tread half the time). What changes its pace lies anywhere on
    // the way.
    for (const auto& [failure, early] : {std::pair{3.0, 3.0}, std::pair{9.8, never}}) {
        const std::vector<double> paced = chain_points(failure, early);
        ASSERT_FALSE(paced.empty());
        EXPECT_LT(*std::min_element(paced.begin(), paced.end()), 1.0)
            << "came nearest at " << failure << " s: never branched before the first part was met";
        EXPECT_LT(*std::max_element(paced.begin(), paced.end()), failure) << "nothing after it went wrong changes it";
    }
}

TEST(BranchPlanner, ABodyAtRestIsBranchedWhileWhatItIsJointedToStillMoves) {
    // C, which misses its part (going wrong at 6 s), lies still from 2.6 s; D, hinged to it, hits
    // the floor at 4 and 5 s (a forearm at rest while the body it hangs from slides on). Alone, C
    // is branched only until it rests; hinged to D, also at D's impacts.
    for (const bool hinged : {false, true}) {
        ThreeBoxes s;
        s.scene.bodies.push_back(fixtures::box("D", {1.5, 0, 0.2}));
        if (hinged) s.scene.constraints.push_back(fixtures::hinge("CD", "C", "D", {1.25, 0, 0.2}));
        for (double t : {4.0, 5.0}) s.world.contacts.push_back({t, 4, 0, 1.0});
        s.world.metrics.push_back({"time_to_rest_s", {0, 0, 0, 2.6, 5.2}});
        s.score.misses = {{2, 0.3, 6.0, 0.0, {3}}};
        s.score.first_unmet = 2;
        s.score.failing_bodies = {3};
        BranchPlanner planner(s.scene, s.parts, 7);
        double latest = 0;
        Branch b;
        for (size_t n = 0; planner.choose(0, s.world, s.score, b); ++n) {
            ASSERT_LT(n, 50u);
            latest = std::max(latest, seconds(b));
        }
        if (hinged) EXPECT_DOUBLE_EQ(latest, 5.0) << "D's last impact";
        else EXPECT_LE(latest, 2.6) << "nothing of C moves after it rests";
    }
}

// Every positive part met, then C entered a box it must keep out of (a fourth, negative part)
// at 6 s; C hits the floor at `impacts`.
ThreeBoxes broken_at_six(const std::vector<double>& impacts) {
    ThreeBoxes s;
    s.world.contacts.clear();
    for (double t : impacts) s.world.contacts.push_back({t, 3, 0, 1.0});
    QueryBox keep_out;
    keep_out.bodies = {3};
    keep_out.negative = true;
    s.parts.push_back(keep_out);
    s.score.boxes_met = 3;
    s.score.met = {1, 1, 1, 0};
    s.score.met_time_s = {8.0, 8.0, 8.0, 0};
    s.score.misses = {{3, 0.5, 6.0, 0.0, {3}}};
    s.score.first_unmet = 3;
    s.score.closeness = 0.5;
    s.score.violation_time_s = 6.0;
    s.score.failure_time_s = 6.0;
    s.score.failing_bodies = {3};
    return s;
}

TEST(BranchPlanner, ABreakIsBranchedLateInEachLengthOfItsSpanHoweverOftenOthersFailed) {
    // C broke its keep-out box at 6 s; it hits the floor every 0.25 s. Every refinement fails. A failure in one length
    // of the span says nothing of how late to branch in another: a length first tried after
    // failures elsewhere is branched late in it, not where those failures pushed it (on the
    // staircase, a figure that stepped out of the footprint 39.6 s into 40 was branched in the
    // last length only at its start, 10 s before, after 12 failures earlier; branched by hand at
    // 37.5 s, 5 of 16 children kept in).
    std::vector<double> impacts;
    for (double t = 0.25; t < 9.5; t += 0.25) impacts.push_back(t);
    const ThreeBoxes s = broken_at_six(impacts);
    // Over many searches (seeds), where in a length its first point lies, for lengths first tried
    // after 3 or more failures (which would move a try 7 points, more than a length holds, back).
    double offsets = 0;
    size_t lengths = 0;
    for (uint64_t seed = 1; seed <= 20; ++seed) {
        BranchPlanner planner(s.scene, s.parts, seed);
        std::set<size_t> lengths_seen;
        Branch b;
        for (size_t n = 0; planner.choose(0, s.world, s.score, b); ++n) {
            ASSERT_LT(n, 50u);
            const double t = seconds(b);
            EXPECT_LT(t, 6.0) << "nothing after the break counts";
            const size_t length = std::min<size_t>(3, static_cast<size_t>(t / 1.5));
            if (lengths_seen.insert(length).second && n >= 3) {
                offsets += t - 1.5 * static_cast<double>(length);
                ++lengths;
            }
            planner.note_children(0, 3.5, {{100 + n, 3.5}}, 0.02);
        }
    }
    ASSERT_GT(lengths, 20u);
    EXPECT_GE(offsets / static_cast<double>(lengths), 0.75)
        << "a length first tried after failures elsewhere is branched, on average, " << offsets / lengths
        << " s after its start (of 1.5 s)";
}

TEST(BranchPlanner, ABreakIsNeverBranchedWhereNoImpactComesBeforeIt) {
    // C broke its keep-out box at 6 s; it hit the floor every 0.25 s until 5 s, and again from
    // 7 s. A branch between 5 and 6 s perturbs C only after the break, so its children
    // all break as their parent did (the staircase's figure, branched 0.03 s before its arm went
    // out, made 8 children no different from it, 5 times over).
    std::vector<double> impacts;
    for (double t = 0.25; t <= 5.0; t += 0.25) impacts.push_back(t);
    for (double t = 7.0; t < 9.5; t += 0.25) impacts.push_back(t);
    const ThreeBoxes s = broken_at_six(impacts);
    BranchPlanner planner(s.scene, s.parts, 7);
    size_t chosen = 0;
    Branch b;
    while (planner.choose(0, s.world, s.score, b)) {
        ASSERT_LT(++chosen, 50u);
        EXPECT_LE(seconds(b), 5.0) << "no impact of C between this branch and the break";
    }
    EXPECT_GT(chosen, 10u);
}

}  // namespace
}  // namespace mwb
