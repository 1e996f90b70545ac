// Goals on hand-made paths: when a path first touches a box, the order of boxes, and how close a
// world comes to the first box it misses.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>

#include "query/GoalScore.h"
#include "query/PathIndex.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;
const Matrix4 kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// Orthographic camera looking down -z at the square x, y in [-10, 10], depth 1..100: a screen
// box (pixels of a 2000 px view) covers x in [x0, x1], y in [y0, y1].
Frustum slab(double x0, double x1, double y0, double y1) {
    const Matrix4 projection{0.1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, -2.0 / 99, -101.0 / 99, 0, 0, 0, 1};
    return make_screen_frustum(kIdentity, projection, 2000, 2000, (x0 + 10) * 100, (y0 + 10) * 100, (x1 + 10) * 100,
                               (y1 + 10) * 100);
}

QueryBox box(double x0, double x1, double y0, double y1, std::vector<uint32_t> bodies, int32_t after = -1,
             bool negative = false) {
    QueryBox b;
    b.frustum = slab(x0, x1, y0, y1);
    b.bodies = std::move(bodies);
    b.after = after;
    b.negative = negative;
    return b;
}

// Entry times are where the 30 Hz polyline enters, which is linear between samples.
constexpr double kTimeTolerance = 1e-3;

// A path through (x, y) waypoints at 1 waypoint per second, sampled at 30 Hz (stride 4 of 120 Hz).
PathTree path_through(const std::vector<std::pair<double, double>>& waypoints) {
    std::vector<float> points;
    for (size_t w = 0; w + 1 < waypoints.size(); ++w)
        for (int k = 0; k < 30; ++k) {
            const double u = k / 30.0;
            points.insert(points.end(), {static_cast<float>(waypoints[w].first * (1 - u) + waypoints[w + 1].first * u),
                                         static_cast<float>(waypoints[w].second * (1 - u) + waypoints[w + 1].second * u),
                                         -5.0f});
        }
    points.insert(points.end(), {static_cast<float>(waypoints.back().first), static_cast<float>(waypoints.back().second),
                                 -5.0f});
    const auto last_frame = static_cast<uint32_t>(120 * (waypoints.size() - 1));
    return PathTree(points, 4, last_frame, 120);
}

TEST(Frustum, FirstTouchIsWhereTheSegmentEntersTheBox) {
    const Frustum f = slab(0, 1, 0, 1);
    EXPECT_NEAR(f.first_touch({-3, 0.5, -5}, {3, 0.5, -5}, 0, 1), 0.5, 1e-9);   // enters at x = 0
    EXPECT_NEAR(f.first_touch({-3, 0.5, -5}, {3, 0.5, -5}, 0.6, 1), 0.6, 1e-9);  // already inside at 0.6
    EXPECT_LT(f.first_touch({-3, 0.5, -5}, {3, 0.5, -5}, 0.7, 1), 0);          // left at x = 1 (u = 2/3)
    EXPECT_NEAR(f.first_touch({-3, 0.5, -5}, {3, 0.5, -5}, 0, 1, 0.6), 0.4, 1e-9);  // a 0.6 m body reaches in sooner
}

TEST(Frustum, ViewRelativeDistanceCountsBoxSizes) {
    const Frustum f = slab(0, 2, 0, 1);  // 2 m wide, 1 m high
    EXPECT_DOUBLE_EQ(f.view_relative_distance({1, 0.5, -5}), 0);
    EXPECT_NEAR(f.view_relative_distance({3, 0.5, -5}), 0.5, 1e-9);    // 1 m right: half a width
    EXPECT_NEAR(f.view_relative_distance({1, 3, -5}), 2.0, 1e-9);      // 2 m above: two heights
    EXPECT_NEAR(f.view_relative_distance({3, 3, -5}), 2.0, 1e-9);      // the larger of the two
    EXPECT_NEAR(f.view_relative_distance({3, 0.5, -5}, 0.5), 0.25, 1e-9);  // a 0.5 m body is half as far
}

TEST(PathTree, FirstTouchTimeIsWhenThePathEnters) {
    // From x = -5 at 1 m/s: enters x in [0, 1] at t = 5 s, leaves at 6 s.
    const PathTree tree = path_through({{-5, 0.5}, {-4, 0.5}, {-3, 0.5}, {-2, 0.5}, {-1, 0.5}, {0, 0.5}, {1, 0.5},
                                        {2, 0.5}, {3, 0.5}});
    const Frustum f = slab(0, 1, 0, 1);
    EXPECT_NEAR(tree.first_touch_time(f, {}, 0), 5.0, kTimeTolerance);
    EXPECT_NEAR(tree.first_touch_time(f, {5.5, 9}, 0), 5.5, kTimeTolerance);
    EXPECT_LT(tree.first_touch_time(f, {6.2, 9}, 0), 0);
    EXPECT_LT(tree.first_touch_time(f, {0, 4.9}, 0), 0);
    EXPECT_NEAR(tree.first_touch_time(f, {}, 0.5), 4.5, kTimeTolerance);  // swept: half a metre sooner
}

// Random walks and boxes: the tree's first touch is the brute force's, and it is the earliest:
// nothing touches before it.
TEST(PathTree, FirstTouchTimeEqualsBruteForceAndNothingTouchesEarlier) {
    PortableRandom random(99);
    int touching = 0, total = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const size_t n = 2 + static_cast<size_t>(random.uniform(0, 300));
        std::vector<float> points;
        Vec3 p{random.uniform(-3, 3), random.uniform(-3, 3), -5};
        for (size_t k = 0; k < n; ++k) {
            for (int a = 0; a < 2; ++a) p[a] += random.uniform(-0.15, 0.15);
            points.insert(points.end(), {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
        }
        const double hold = random.uniform01() < 0.5 ? 4.0 * (n - 1) / 120 + random.uniform(0, 5) : 0.0;
        const PathTree tree(points, 4, static_cast<uint32_t>(4 * (n - 1)), 120, hold);
        for (int b = 0; b < 20; ++b) {
            const double x0 = random.uniform(-5, 2), y0 = random.uniform(-5, 2);
            const Frustum f = slab(x0, x0 + random.uniform(0.3, 5), y0, y0 + random.uniform(0.3, 5));
            TimeWindow window;
            if (random.uniform01() < 0.5) {
                const double t0 = random.uniform(0, 10);
                window = {t0, t0 + random.uniform(0, 4)};
            }
            const double radius = random.uniform01() < 0.3 ? random.uniform(0, 0.5) : 0.0;
            const double t = tree.first_touch_time(f, window, radius);
            ASSERT_NEAR(t, tree.first_touch_time_brute_force(f, window, radius), 1e-9) << trial << " " << b;
            ASSERT_EQ(t >= 0, tree.touches(f, window, radius));
            if (t > 0 && t - 1e-6 > (window.empty() ? 0.0 : window.lo_s)) {
                const TimeWindow before{window.empty() ? 0.0 : window.lo_s, t - 1e-6};
                ASSERT_FALSE(tree.touches(f, before, radius)) << trial << " " << b;
            }
            touching += t >= 0;
            ++total;
        }
    }
    EXPECT_GT(touching, total / 10);
    EXPECT_LT(touching, total * 9 / 10);
}

TEST(GoalOrder, FollowsAfterAndRefusesCyclesAndBadReferences) {
    std::vector<QueryBox> boxes{box(0, 1, 0, 1, {0}, 2), box(0, 1, 0, 1, {0}, 0), box(0, 1, 0, 1, {0})};
    EXPECT_EQ(goal_order(boxes), (std::vector<size_t>{2, 0, 1}));
    boxes[2].after = 1;  // 0 -> 1 -> 2 -> 0
    EXPECT_THROW(goal_order(boxes), std::invalid_argument);
    boxes[2].after = 2;
    EXPECT_THROW(goal_order(boxes), std::invalid_argument);
    boxes[2].after = 7;
    EXPECT_THROW(goal_order(boxes), std::invalid_argument);
    // Unordered boxes keep the list's order.
    EXPECT_EQ(goal_order({box(0, 1, 0, 1, {0}), box(0, 1, 0, 1, {0})}), (std::vector<size_t>{0, 1}));
}

TEST(GoalOrder, TheAftersAloneGiveTheOrderOfTheParts) {
    // What the add-on's After menu asks: every list of afters orders (or refuses) as the goal would.
    PortableRandom random(11);
    for (int trial = 0; trial < 500; ++trial) {
        const auto n = static_cast<size_t>(std::floor(random.uniform(1, 7)));
        std::vector<int32_t> afters;
        std::vector<QueryBox> parts;
        for (size_t k = 0; k < n; ++k) {
            // Mostly unordered or another part; now and then itself or a part past the end.
            afters.push_back(static_cast<int32_t>(std::floor(random.uniform(-1.5, static_cast<double>(n) + 1))));
            parts.push_back(box(0, 1, 0, 1, {0}, afters.back()));
        }
        bool refused_parts = false, refused_afters = false;
        std::vector<size_t> by_parts, by_afters;
        try {
            by_parts = goal_order(parts);
        } catch (const std::invalid_argument&) {
            refused_parts = true;
        }
        try {
            by_afters = goal_order(afters);
        } catch (const std::invalid_argument&) {
            refused_afters = true;
        }
        EXPECT_EQ(refused_parts, refused_afters);
        EXPECT_EQ(by_parts, by_afters);
    }
    EXPECT_EQ(goal_order(std::vector<int32_t>{-1, 0, 1}), (std::vector<size_t>{0, 1, 2}));
    EXPECT_THROW(goal_order(std::vector<int32_t>{2, 0, 1}), std::invalid_argument);
}

// Three cups in a row at x = 2, 4, 6; the marble must tip them in turn.
std::vector<QueryBox> three_cups() {
    return {box(1.5, 2.5, 0, 1, {0}), box(3.5, 4.5, 0, 1, {0}, 0), box(5.5, 6.5, 0, 1, {0}, 1)};
}

TEST(GoalScore, OrderedBoxesCountOnlyInTurn) {
    const std::vector<QueryBox> cups = three_cups();
    const std::vector<size_t> order = goal_order(cups);
    const std::vector<double> radii{0.1};
    // In turn: cup 1 at t = 1, cup 2 at t = 2, cup 3 at t = 3.
    GoalScore s = score_goal({path_through({{0, 0.5}, {2, 0.5}, {4, 0.5}, {6, 0.5}})}, radii, cups, order);
    EXPECT_EQ(s.boxes_met, 3u);
    EXPECT_EQ(s.first_unmet, -1);
    EXPECT_NEAR(s.met_time_s[1], 2.0 - 0.5 / 2, kTimeTolerance);  // enters cup 2's box at x = 3.5
    // Cup 3 first (t = 1), then cups 1 and 2: only cups 1 and 2 count.
    s = score_goal({path_through({{4, 3}, {6, 0.5}, {6, 3}, {2, 0.5}, {4, 0.5}, {4, 3}})}, radii, cups, order);
    EXPECT_EQ(s.boxes_met, 2u);
    EXPECT_EQ(s.first_unmet, 2);
    // Cup 2 without cup 1: nothing counts, the first unmet box is cup 1.
    s = score_goal({path_through({{4, 3}, {4, 0.5}, {6, 0.5}})}, radii, cups, order);
    EXPECT_EQ(s.boxes_met, 0u);
    EXPECT_EQ(s.first_unmet, 0);
    // Without the order, the same path meets cups 2 and 3.
    std::vector<QueryBox> unordered = three_cups();
    for (QueryBox& b : unordered) b.after = -1;
    s = score_goal({path_through({{4, 3}, {4, 0.5}, {6, 0.5}})}, radii, unordered, goal_order(unordered));
    EXPECT_EQ(s.boxes_met, 2u);
    EXPECT_EQ(s.first_unmet, 0);
}

TEST(GoalScore, ClosenessOfAPositiveBoxIsTheNearestApproachInBoxSizes) {
    const std::vector<QueryBox> goal{box(0, 1, 0, 1, {0, 1})};
    // Body 0 passes 2 m above the box (two box heights) at t = 1; body 1 passes 0.5 m to its
    // right at t = 2: the nearest, half a box width.
    GoalScore s = score_goal({path_through({{-2, 3}, {0.5, 3}, {4, 3}}), path_through({{3, 0.5}, {3, 0.5}, {1.5, 0.5}, {3, 0.5}})},
                             {0.1, 0.1}, goal, goal_order(goal));
    EXPECT_EQ(s.boxes_met, 0u);
    EXPECT_NEAR(s.closeness, 1 / 1.5, 1e-3);
    EXPECT_NEAR(s.failure_time_s, 2.0, kTimeTolerance);
    EXPECT_EQ(s.failing_bodies, (std::vector<uint32_t>{1}));
    // Nearer is closer, and a met box always counts for more than any closeness.
    const GoalScore nearer = score_goal({path_through({{-2, 3}, {0.5, 1.2}, {4, 3}}), path_through({{3, 0.5}, {3, 0.5}})},
                                        {0.1, 0.1}, goal, goal_order(goal));
    EXPECT_GT(nearer.closeness, s.closeness);
    const GoalScore met = score_goal({path_through({{-2, 3}, {0.5, 0.5}, {4, 3}}), path_through({{3, 0.5}, {3, 0.5}})},
                                     {0.1, 0.1}, goal, goal_order(goal));
    EXPECT_EQ(met.boxes_met, 1u);
    EXPECT_GT(met.value(), nearer.value());
    EXPECT_LT(nearer.value(), 1.0);
}

TEST(GoalScore, ABoxWithAWindowKnowsWhenTheWorldWasInItTooSoon) {
    // Cup 2 after cup 1, in the window 4-5 s (the world is 5 s long).
    std::vector<QueryBox> cups{box(1.5, 2.5, 0, 1, {0}), box(3.5, 4.5, 0, 1, {0}, 0)};
    cups[1].window = {4.0, 5.0};
    const auto early_of = [&](const std::vector<std::pair<double, double>>& waypoints) {
        const GoalScore s = score_goal({path_through(waypoints)}, {0.1}, cups, goal_order(cups));
        EXPECT_EQ(s.boxes_met, 1u);
        EXPECT_EQ(s.misses.size(), 1u);
        return s.misses.empty() ? -1.0 : s.misses.front().early_visit_s;
    };
    // Through cup 1 and cup 2 by 2 s, and on: there too soon, from x = 3.5 (1.75 s).
    EXPECT_NEAR(early_of({{0, 0.5}, {2, 0.5}, {4, 0.5}, {6, 0.5}, {8, 0.5}, {8, 0.5}}), 1.75, kTimeTolerance);
    // Stopped short of cup 2: never in it.
    EXPECT_TRUE(std::isinf(early_of({{0, 0.5}, {2, 0.5}, {3, 0.5}, {3, 0.5}, {3, 0.5}, {3, 0.5}})));
    // In cup 2 only before cup 1 was met: that visit does not count.
    EXPECT_TRUE(std::isinf(early_of({{4, 0.5}, {2, 0.5}, {0, 0.5}, {0, 0.5}, {0, 0.5}, {0, 0.5}})));
}

TEST(GoalScore, EveryPartItCouldMeetNextIsListedNearestFirst) {
    // Body 0 meets its box; body 1 passes half a box from its own, body 2 three boxes from its own.
    const std::vector<QueryBox> goal{box(0, 1, 0, 1, {0}), box(4, 5, 0, 1, {1}), box(-5, -4, 0, 1, {2})};
    const GoalScore s = score_goal({path_through({{0.5, 3}, {0.5, 0.5}}), path_through({{3, 3}, {3.5, 0.5}}),
                                    path_through({{-1, 3}, {-1, 0.5}})},
                                   {0.1, 0.1, 0.1}, goal, goal_order(goal));
    EXPECT_EQ(s.boxes_met, 1u);
    ASSERT_EQ(s.misses.size(), 2u);
    EXPECT_EQ(s.misses[0].part, 1);
    EXPECT_EQ(s.misses[0].failing_bodies, (std::vector<uint32_t>{1}));
    EXPECT_NEAR(s.misses[0].closeness, 1 / 1.5, 1e-3);
    EXPECT_EQ(s.misses[1].part, 2);
    EXPECT_EQ(s.misses[1].failing_bodies, (std::vector<uint32_t>{2}));
    EXPECT_NEAR(s.misses[1].closeness, 1 / 4.0, 1e-3);
    // The nearest is the one the score reports.
    EXPECT_EQ(s.first_unmet, 1);
    EXPECT_EQ(s.closeness, s.misses[0].closeness);
    // Ordered parts: only the next one in the order is listed.
    std::vector<QueryBox> ordered = goal;
    ordered[2].after = 1;
    const GoalScore in_turn = score_goal({path_through({{0.5, 3}, {0.5, 0.5}}), path_through({{3, 3}, {3.5, 0.5}}),
                                          path_through({{-1, 3}, {-1, 0.5}})},
                                         {0.1, 0.1, 0.1}, ordered, goal_order(ordered));
    ASSERT_EQ(in_turn.misses.size(), 1u);
    EXPECT_EQ(in_turn.misses[0].part, 1);
}

TEST(GoalScore, ClosenessOfANegativeBoxIsHowBrieflyThePathStaysInside) {
    std::vector<QueryBox> goal{box(0, 1, 0, 1, {0, 1}, -1, true)};
    goal[0].window = {0, 4};
    // Body 1 enters at t = 2 (x = 0) and stays to the end (t = 4): inside for half the window.
    // Body 0 enters later, at t = 3.
    GoalScore s = score_goal({path_through({{5, 0.5}, {5, 0.5}, {5, 0.5}, {0.5, 0.5}, {0.5, 0.5}}),
                              path_through({{-4, 0.5}, {-2, 0.5}, {0, 0.5}, {0.5, 0.5}, {0.5, 0.5}})},
                             {0.1, 0.1}, goal, goal_order(goal));
    EXPECT_EQ(s.boxes_met, 0u);
    ASSERT_EQ(s.misses.size(), 1u);
    EXPECT_NEAR(s.misses[0].closeness, 0.5, 0.02);
    EXPECT_NEAR(s.failure_time_s, 2.0, kTimeTolerance);
    EXPECT_EQ(s.failing_bodies, (std::vector<uint32_t>{1, 0}));
    // Inside only briefly: closer to meeting it.
    const GoalScore brief = score_goal({path_through({{5, 0.5}, {5, 0.5}, {5, 0.5}, {5, 0.5}, {5, 0.5}}),
                                        path_through({{-4, 0.5}, {-2, 0.5}, {-0.5, 0.5}, {0.5, 0.5}, {4, 0.5}})},
                                       {0.1, 0.1}, goal, goal_order(goal));
    EXPECT_GT(brief.misses[0].closeness, 0.8);
    EXPECT_LT(brief.misses[0].closeness, 1.0);
}

// An orientation part of `bodies`: axis z within `within_deg` of `target`.
QueryBox upright(std::vector<uint32_t> bodies, double within_deg, TimeWindow window, Vec3 target = {0, 0, 1},
                 bool negative = false, double longer_than_s = 0) {
    QueryBox part;
    part.bodies = std::move(bodies);
    part.window = window;
    part.negative = negative;
    part.orientation = OrientationTest{{0, 0, 1}, target, within_deg * kPi / 180, longer_than_s};
    return part;
}

// Rotations about x at the path's points: from `from_deg` to `to_deg`, evenly over the first
// `turn_s` seconds of a 30 Hz path of `points` points, then held.
std::vector<Quat> turning_about_x(size_t points, double from_deg, double to_deg, double turn_s) {
    std::vector<Quat> out;
    for (size_t k = 0; k < points; ++k) {
        const double u = std::min(1.0, (k / 30.0) / turn_s);
        out.push_back(quat_from_axis_angle({1, 0, 0}, (from_deg + (to_deg - from_deg) * u) * kPi / 180));
    }
    return out;
}

TEST(GoalScore, AnOrientationPartHoldsWhileTheAxisStaysWithinItsTolerance) {
    // One body tips over about x, from upright to on its side (z turned to -y) in 3 s, then lies still.
    const PathTree path = path_through({{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}});
    const BodyOrientations tipping{turning_about_x(path.point_count(), 0, 90, 3)};
    const auto met = [&](const QueryBox& part) {
        const std::vector<QueryBox> goal{part};
        return score_goal({path}, {0.1}, goal, goal_order(goal), true, &tipping);
    };
    EXPECT_EQ(met(upright({0}, 20, {0, 0.5})).boxes_met, 1u);   // still upright for the first half second
    const GoalScore late = met(upright({0}, 20, {3, 4}));        // on its side at the end
    EXPECT_EQ(late.boxes_met, 0u);
    EXPECT_EQ(late.first_unmet, 0);
    // Its worst is 90°: 1 - cos 90° is (1 - cos 20°) times 1 / (1 - cos 20°), an excess of
    // cos 20° / (1 - cos 20°) tolerances.
    const double tolerance = 1 - std::cos(20 * kPi / 180);
    EXPECT_NEAR(late.closeness, 1 / (1 + std::cos(20 * kPi / 180) / tolerance), 1e-6);
    // It went wrong as it tipped past 20°: at 20/90 of the 3 s turn.
    EXPECT_NEAR(late.failure_time_s, 3.0 * 20 / 90, 1.0 / 30 + 1e-9);
    EXPECT_EQ(late.failing_bodies, (std::vector<uint32_t>{0}));
    // Less tipped is closer, and meeting the part counts for more than any closeness.
    const BodyOrientations leaning{turning_about_x(path.point_count(), 0, 30, 3)};
    const std::vector<QueryBox> goal{upright({0}, 20, {3, 4})};
    const GoalScore nearer = score_goal({path}, {0.1}, goal, goal_order(goal), true, &leaning);
    EXPECT_GT(nearer.closeness, late.closeness);
    EXPECT_LT(nearer.value(), met(upright({0}, 20, {0, 0.5})).value());

    // Negative: lying on its side (z within 20° of -y) for more than a given time. It lies so from
    // 70° on (7/9 of the turn, 2.33 s) to the end of its held pose (4 s): 1.67 s.
    const Vec3 side{0, -1, 0};
    EXPECT_EQ(met(upright({0}, 20, {}, side, true, 2.0)).boxes_met, 1u);
    const GoalScore lying = met(upright({0}, 20, {}, side, true, 0.5));
    EXPECT_EQ(lying.boxes_met, 0u);
    EXPECT_NEAR(lying.failure_time_s, 3.0 * 70 / 90, 1.0 / 30 + 1e-9);
    EXPECT_NEAR(lying.misses[0].closeness, 1 - 1.67 / 4, 0.03);
    EXPECT_EQ(met(upright({0}, 20, {0, 2}, side, true)).boxes_met, 1u);  // not yet lying in the first 2 s

    // Without the rotations an orientation part cannot be scored, and the index refuses it.
    const std::vector<QueryBox> part{upright({0}, 20, {})};
    EXPECT_THROW(score_goal({path}, {0.1}, part, goal_order(part)), std::invalid_argument);
    PathIndex index({0.1});
    EXPECT_THROW(index.query(part), std::invalid_argument);
}

TEST(GoalScore, PartsMetAfterTheFirstEntryIntoANegativeBoxDoNotCountTowardItsValue) {
    // Boxes A, B, C along x in turn on body 0; a negative box N high up on both bodies.
    std::vector<QueryBox> goal{box(0, 1, 0, 1, {0}), box(2, 3, 0, 1, {0}, 0), box(4, 5, 0, 1, {0}, 1),
                               box(-10, 10, 5, 6, {0, 1}, -1, true)};
    const std::vector<double> radii{0.1, 0.1};
    // Body 0 meets A at 0.8 s, B and C later; body 1 reaches up into N at 1.91 s (y = 5 of 5.5).
    const auto tumble = path_through({{0.5, 3}, {0.5, 0.5}, {0.5, 0.5}, {2.5, 0.5}, {4.5, 0.5}});
    const auto poking_out = path_through({{-8, 0}, {-8, 0}, {-8, 5.5}, {-8, 0}, {-8, 0}});
    const GoalScore all_but_n = score_goal({tumble, poking_out}, radii, goal, goal_order(goal));
    EXPECT_EQ(all_but_n.boxes_met, 3u);
    EXPECT_NEAR(all_but_n.violation_time_s, 1 + 5 / 5.5, 1.0 / 30);
    EXPECT_EQ(all_but_n.parts_before_violation, 1u);  // A only: B and C came after
    EXPECT_EQ(all_but_n.positive_parts_before_violation, 1u);  // A: a mend can keep it
    // Body 0 meets A and stops short of B; body 1 stays low: fewer boxes, but nothing to undo.
    const auto stopping = path_through({{0.5, 3}, {0.5, 0.5}, {1.5, 0.5}, {1.5, 0.5}, {1.5, 0.5}});
    const auto staying = path_through({{-8, 0}, {-8, 0}, {-8, 0}, {-8, 0}, {-8, 0}});
    const GoalScore a_and_n = score_goal({stopping, staying}, radii, goal, goal_order(goal));
    EXPECT_EQ(a_and_n.boxes_met, 2u);
    EXPECT_FALSE(std::isfinite(a_and_n.violation_time_s));
    EXPECT_EQ(a_and_n.parts_before_violation, 2u);
    EXPECT_EQ(a_and_n.positive_parts_before_violation, 1u);  // N kept is not a positive part
    EXPECT_GT(a_and_n.value(), all_but_n.value());
    // An orientation part counts when its window closed before the violation, not when it closes after.
    const BodyOrientations still{turning_about_x(tumble.point_count(), 0, 0, 1),
                                 turning_about_x(poking_out.point_count(), 0, 0, 1)};
    goal.push_back(upright({0}, 20, {0, 1}));
    goal.push_back(upright({0}, 20, {0, 3}));
    const GoalScore upright_too = score_goal({tumble, poking_out}, radii, goal, goal_order(goal), true, &still);
    EXPECT_EQ(upright_too.boxes_met, 5u);
    EXPECT_EQ(upright_too.parts_before_violation, 2u);
    EXPECT_EQ(upright_too.positive_parts_before_violation, 2u);
}

TEST(GoalScore, AWorldThatBrokeANegativePartIsCloserTheLaterItBroke) {
    // A then B on body 0; a negative box N high up on body 1. Both worlds meet A only, then body 1
    // pokes into N: one at 1.5 s and briefly, the other at 2.91 s and stays (4 s paths).
    const std::vector<QueryBox> goal{box(0, 1, 0, 1, {0}), box(2, 3, 0, 1, {0}, 0), box(-10, 10, 5, 6, {1}, -1, true)};
    const std::vector<double> radii{0.1, 0.1};
    const auto meets_a = path_through({{0.5, 3}, {0.5, 0.5}, {1.2, 0.5}, {1.2, 0.5}, {1.2, 0.5}});
    const auto briefly_early = path_through({{-8, 0}, {-8, 4}, {-8, 6}, {-8, 0}, {-8, 0}});
    const auto late_for_good = path_through({{-8, 0}, {-8, 0}, {-8, 0}, {-8, 5.5}, {-8, 5.5}});
    const GoalScore early = score_goal({meets_a, briefly_early}, radii, goal, goal_order(goal));
    const GoalScore late = score_goal({meets_a, late_for_good}, radii, goal, goal_order(goal));
    ASSERT_EQ(early.parts_before_violation, 1u);
    ASSERT_EQ(late.parts_before_violation, 1u);
    EXPECT_NEAR(early.violation_time_s, 1.5, 1.0 / 30);
    EXPECT_NEAR(late.violation_time_s, 2 + 5 / 5.5, 1.0 / 30);
    // Inside N for less of the window, but what it kept before breaking it is shorter.
    const auto n_closeness = [](const GoalScore& s) {
        for (const GoalScore::Miss& m : s.misses)
            if (m.part == 2) return m.closeness;
        return -1.0;
    };
    EXPECT_GT(n_closeness(early), n_closeness(late));
    EXPECT_NEAR(early.closeness, 1.5 / 4, 0.01);
    EXPECT_NEAR(late.closeness, (2 + 5 / 5.5) / 4, 0.01);
    EXPECT_GT(late.value(), early.value());
    // Breaking N never outranks meeting one more part before it.
    const GoalScore clean_a = score_goal({meets_a, path_through({{-8, 0}, {-8, 0}, {-8, 0}, {-8, 0}, {-8, 0}})},
                                         radii, goal, goal_order(goal));
    EXPECT_GT(clean_a.value(), late.value());
    // A search takes worlds as the same only if they also broke at the same moment: one broken at
    // 1 s of a 4 s path and one at 2 s of an 8 s path are equally late, and both worth refining.
    GoalScore quarter_of_4s = early, quarter_of_8s = early;
    quarter_of_4s.violation_time_s = 1.0;
    quarter_of_8s.violation_time_s = 2.0;
    quarter_of_4s.closeness = quarter_of_8s.closeness = 0.25;
    EXPECT_EQ(quarter_of_4s.value(), quarter_of_8s.value());
    EXPECT_NE(quarter_of_4s.search_key(), quarter_of_8s.search_key());
    EXPECT_EQ(early.search_key(), score_goal({meets_a, briefly_early}, radii, goal, goal_order(goal)).search_key());
    EXPECT_NE(early.search_key(), late.search_key());
}

TEST(GoalScore, OfTwoWorldsMeetingAsManyPartsTheOneWithMoreTimeToSpareIsNearer) {
    // A then B (x in [4, 5], in the last second of a 4 s path): both worlds meet A and stop as
    // far short of B, one having met A before 1 s, the other before 3 s.
    const std::vector<QueryBox> goal{box(0, 1, 0, 1, {0}), box(4, 5, 0, 1, {0}, 0)};
    std::vector<QueryBox> in_time = goal;
    in_time[1].window = {3, 4};
    const auto quick = path_through({{0.5, -3}, {0.5, 0.5}, {2, 0.5}, {2, 0.5}, {2, 0.5}});
    const auto slow = path_through({{0.5, -9}, {0.5, -6}, {0.5, -3}, {0.5, 0.5}, {2, 0.5}});
    for (const std::vector<QueryBox>& g : {goal, in_time}) {
        const GoalScore q = score_goal({quick}, {0.1}, g, goal_order(g));
        const GoalScore s = score_goal({slow}, {0.1}, g, goal_order(g));
        ASSERT_EQ(q.boxes_met, 1u);
        ASSERT_EQ(s.boxes_met, 1u);
        EXPECT_LT(q.met_time_s[0], s.met_time_s[0]);
        EXPECT_GT(q.value(), s.value());
        EXPECT_LT(q.value(), 2.0);  // still less than meeting B
    }
}

TEST(GoalScore, APosePartOverSeveralBodiesIsNearerTheFewerOfThemAreOff) {
    // Five dice that must end up: a world with one of them on its side scores nearer than one with
    // all five on their sides, and the blame falls on the dice that are off.
    const PathTree still = path_through({{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}});
    const std::vector<PathView> paths(5, still);
    const std::vector<double> radii(5, 0.1);
    const std::vector<QueryBox> goal{upright({0, 1, 2, 3, 4}, 20, {3, 4})};
    const std::vector<Quat> up = turning_about_x(still.point_count(), 0, 0, 1);
    const std::vector<Quat> side = turning_about_x(still.point_count(), 0, 90, 1);
    const BodyOrientations one_off{up, up, side, up, up};
    const BodyOrientations all_off{side, side, side, side, side};
    const GoalScore one = score_goal(paths, radii, goal, goal_order(goal), true, &one_off);
    const GoalScore five = score_goal(paths, radii, goal, goal_order(goal), true, &all_off);
    EXPECT_EQ(one.boxes_met, 0u);
    EXPECT_GT(one.closeness, five.closeness);
    EXPECT_EQ(one.failing_bodies, (std::vector<uint32_t>{2}));
    EXPECT_EQ(five.failing_bodies.size(), 5u);
    // Four held count 1 each; the one on its side as it would alone.
    const std::vector<QueryBox> alone{upright({2}, 20, {3, 4})};
    const GoalScore single = score_goal(paths, radii, alone, goal_order(alone), true, &one_off);
    EXPECT_NEAR(one.closeness, (4 + single.closeness) / 5, 1e-12);
    EXPECT_NEAR(five.closeness, single.closeness, 1e-12);
}

TEST(GoalScore, APoseCountsOnlyOnceItsBodyHasMetItsBox) {
    // Two letters, each to end in its own slot (x in [0, 1] and [4, 5]) and upright, over the last
    // second. Letter 1 stopped beside its slot: upright there or lying there, it has its slot still
    // to reach, and the refinement that takes it there re-runs its pose.
    QueryBox first_slot = box(0, 1, 0, 1, {0}), second_slot = box(4, 5, 0, 1, {1});
    first_slot.window = second_slot.window = {3, 4};
    const std::vector<QueryBox> goal{first_slot, second_slot, upright({0}, 20, {3, 4}), upright({1}, 20, {3, 4})};
    const std::vector<double> radii{0.1, 0.1};
    const PathTree in_first = path_through({{0.5, 3}, {0.5, 0.5}, {0.5, 0.5}, {0.5, 0.5}, {0.5, 0.5}});
    const PathTree beside_second = path_through({{4.5, 3}, {3, 0.5}, {3, 0.5}, {3, 0.5}, {3, 0.5}});
    const PathTree in_second = path_through({{4.5, 3}, {4.5, 0.5}, {4.5, 0.5}, {4.5, 0.5}, {4.5, 0.5}});
    const std::vector<Quat> up = turning_about_x(in_first.point_count(), 0, 0, 1);
    const std::vector<Quat> lying = turning_about_x(in_first.point_count(), 0, 90, 1);
    const BodyOrientations upright_beside{up, up}, lying_beside{up, lying};
    const GoalScore standing = score_goal({in_first, beside_second}, radii, goal, goal_order(goal), true, &upright_beside);
    const GoalScore fallen = score_goal({in_first, beside_second}, radii, goal, goal_order(goal), true, &lying_beside);
    // Met as a query counts every part; the search counts letter 1's pose only in its slot.
    EXPECT_EQ(standing.boxes_met, 3u);
    EXPECT_EQ(fallen.boxes_met, 2u);
    EXPECT_EQ(standing.parts_before_violation, 2u);
    EXPECT_NEAR(standing.value(), fallen.value(), 1e-12);
    // Next for both is letter 1's slot, not its pose.
    EXPECT_EQ(standing.first_unmet, 1);
    EXPECT_EQ(fallen.first_unmet, 1);
    for (const GoalScore::Miss& miss : fallen.misses) EXPECT_NE(miss.part, 3);
    // In its slot but lying, it is a part further on, and its pose is what is next.
    const GoalScore slotted = score_goal({in_first, in_second}, radii, goal, goal_order(goal), true, &lying_beside);
    EXPECT_EQ(slotted.parts_before_violation, 3u);
    EXPECT_EQ(slotted.first_unmet, 3);
    EXPECT_GT(slotted.value(), standing.value());
    // A pose whose window does not overlap the box's is a part of its own.
    std::vector<QueryBox> early_pose = goal;
    early_pose[3].window = {0, 0.5};
    const GoalScore apart =
        score_goal({in_first, beside_second}, radii, early_pose, goal_order(early_pose), true, &upright_beside);
    EXPECT_EQ(apart.parts_before_violation, 3u);
}

TEST(GoalScore, WorldsBreakingANegativePoseTogetherAreToldApartByHowManyBodiesBreakIt) {
    // Eight pins that must all be down in the last second (none within 45° of up for longer than
    // 0.25 s). Those still standing broke it since the start; a world with one standing pin is
    // nearer than one with all eight, and the search is told to branch from the start, when
    // the pins still stood, not when the window opened.
    const PathTree still = path_through({{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}});
    const std::vector<PathView> paths(8, still);
    const std::vector<double> radii(8, 0.1);
    const std::vector<QueryBox> goal{upright({0, 1, 2, 3, 4, 5, 6, 7}, 45, {3, 4}, {0, 0, 1}, true, 0.25)};
    const std::vector<Quat> standing = turning_about_x(still.point_count(), 0, 0, 1);
    const std::vector<Quat> fallen = turning_about_x(still.point_count(), 0, 90, 1);
    BodyOrientations one_standing(8, fallen);
    one_standing[5] = standing;
    const BodyOrientations all_standing(8, standing);
    const GoalScore one = score_goal(paths, radii, goal, goal_order(goal), true, &one_standing);
    const GoalScore eight = score_goal(paths, radii, goal, goal_order(goal), true, &all_standing);
    EXPECT_EQ(one.boxes_met, 0u);
    EXPECT_DOUBLE_EQ(one.violation_time_s, 0.0);
    EXPECT_DOUBLE_EQ(eight.violation_time_s, 0.0);
    EXPECT_EQ(one.failing_bodies, (std::vector<uint32_t>{5}));
    EXPECT_GT(one.violation_closeness, eight.violation_closeness);
    EXPECT_GT(one.value(), eight.value());
    EXPECT_NE(one.search_key(), eight.search_key());
    // A pin that fell and rolled back up at 2 s broke it then.
    BodyOrientations rolled_back(8, fallen);
    rolled_back[3] = turning_about_x(still.point_count(), 90, 0, 2);
    const GoalScore late = score_goal(paths, radii, goal, goal_order(goal), true, &rolled_back);
    EXPECT_NEAR(late.failure_time_s, 2.0 * 45 / 90, 1.0 / 30 + 1e-9);
    // All down: met.
    const BodyOrientations none_standing(8, fallen);
    EXPECT_EQ(score_goal(paths, radii, goal, goal_order(goal), true, &none_standing).boxes_met, 1u);
}

// Rotations a test hands the index: per world, one list of rotations for every body.
class FixedRotations : public RotationSource {
public:
    explicit FixedRotations(std::map<uint64_t, BodyOrientations> worlds) : worlds_(std::move(worlds)) {}
    BodyOrientations rotations_at_path_points(uint64_t world, const std::vector<uint32_t>&) const override {
        return worlds_.at(world);
    }

private:
    std::map<uint64_t, BodyOrientations> worlds_;
};

TEST(PathIndex, PosePartsAreQueriedWithBoxesFromItsRotationSource) {
    // Two worlds of one body moving right at 1 m/s: in world 0 it ends upright, in world 1 on its side.
    const PathTree path = path_through({{0, 0.5}, {1, 0.5}, {2, 0.5}, {3, 0.5}});
    PathIndex index({0.1});
    std::vector<IndexedWorldInput> worlds;
    for (uint64_t w : {0, 1}) {
        IndexedWorldInput in;
        in.world_index = w;
        in.stride = 4;
        in.last_frame = 360;
        in.record_hz = 120;
        std::vector<float> points;
        for (size_t k = 0; k < path.point_count(); ++k) {
            const Vec3 p = path.point(k);
            points.insert(points.end(), {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
        }
        in.polylines = {points};
        in.final_orientations = {Quat{1, 0, 0, 0}};
        worlds.push_back(std::move(in));
    }
    index.add_worlds(std::move(worlds), 1);
    const std::vector<QueryBox> goal{box(2.5, 3.5, 0, 1, {0}), upright({0}, 20, {2, 3})};
    EXPECT_THROW(index.query(goal), std::invalid_argument);  // no rotations yet
    const size_t n = path.point_count();
    index.set_rotation_source(std::make_shared<FixedRotations>(std::map<uint64_t, BodyOrientations>{
        {0, {turning_about_x(n, 0, 0, 1)}}, {1, {turning_about_x(n, 0, 90, 1)}}}));
    const QueryResult both = index.query(goal);
    EXPECT_EQ(both.boxes_satisfied, (std::vector<uint32_t>{2, 1}));
    EXPECT_EQ(both.matching, (std::vector<uint64_t>{0}));
    // The same on two threads, and the parts-met ranking counts the pose part.
    EXPECT_EQ(index.query(goal, 0, false, 2).boxes_satisfied, both.boxes_satisfied);
    const auto ranked = index.rank("boxes_met", {}, Combine::Sum, true, nullptr, nullptr, &goal);
    ASSERT_EQ(ranked.size(), 2u);
    EXPECT_EQ(ranked[0], (std::pair<uint64_t, double>{0, 2.0}));
    // Negative, it keeps the world that is not upright for longer than half a second.
    const std::vector<QueryBox> not_upright{upright({0}, 20, {}, {0, 0, 1}, true, 0.5)};
    EXPECT_EQ(index.query(not_upright).matching, (std::vector<uint64_t>{1}));
    // A score reads the source too.
    EXPECT_EQ(index.score(1, goal, goal_order(goal)).first_unmet, 1);
}

TEST(PathIndex, OrderedQueriesCountAlongTheOrder) {
    PathIndex index({0.1});
    auto world = [](uint64_t w, std::vector<std::pair<double, double>> waypoints) {
        IndexedWorldInput in;
        in.world_index = w;
        in.stride = 4;
        in.last_frame = static_cast<uint32_t>(120 * (waypoints.size() - 1));
        in.record_hz = 120;
        std::vector<float> points;
        for (size_t k = 0; k < waypoints.size(); ++k)
            points.insert(points.end(), {static_cast<float>(waypoints[k].first), static_cast<float>(waypoints[k].second), -5.0f});
        // One point per second: stride 120 frames.
        in.stride = 120;
        in.polylines = {points};
        in.final_orientations = {Quat{1, 0, 0, 0}};
        return in;
    };
    std::vector<IndexedWorldInput> worlds;
    worlds.push_back(world(0, {{0, 0.5}, {2, 0.5}, {4, 0.5}, {6, 0.5}}));          // in turn
    worlds.push_back(world(1, {{6, 0.5}, {6, 3}, {2, 0.5}, {4, 0.5}, {4, 3}}));    // cup 3 too early
    index.add_worlds(std::move(worlds), 1);
    const QueryResult ordered = index.query(three_cups());
    EXPECT_EQ(ordered.boxes_satisfied, (std::vector<uint32_t>{3, 2}));
    EXPECT_EQ(ordered.matching, (std::vector<uint64_t>{0}));
    std::vector<QueryBox> unordered = three_cups();
    for (QueryBox& b : unordered) b.after = -1;
    EXPECT_EQ(index.query(unordered).matching, (std::vector<uint64_t>{0, 1}));
    std::vector<QueryBox> cyclic = three_cups();
    cyclic[0].after = 2;
    EXPECT_THROW(index.query(cyclic), std::invalid_argument);
    EXPECT_EQ(index.score(1, three_cups(), goal_order(three_cups())).first_unmet, 2);
}

}  // namespace
}  // namespace mwb
