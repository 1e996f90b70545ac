#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <set>
#include <thread>

#include "query/BodyMetrics.h"
#include "query/PathIndex.h"
#include "query/RankingMetrics.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;

const Matrix4 kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix4 orthographic(double l, double r, double b, double t, double n, double f) {
    return {2 / (r - l), 0, 0, -(r + l) / (r - l), 0, 2 / (t - b), 0, -(t + b) / (t - b),
            0, 0, -2 / (f - n), -(f + n) / (f - n), 0, 0, 0, 1};
}

Matrix4 perspective(double fov_y, double aspect, double n, double f) {
    const double c = 1 / std::tan(fov_y / 2);
    return {c / aspect, 0, 0, 0, 0, c, 0, 0, 0, 0, -(f + n) / (f - n), -2 * f * n / (f - n), 0, 0, -1, 0};
}

Matrix4 translation(const Vec3& t) { return {1, 0, 0, t[0], 0, 1, 0, t[1], 0, 0, 1, t[2], 0, 0, 0, 1}; }

bool inside(const Frustum& f, const Vec3& p) { return f.touches_segment(p, p, 0, 1); }

TEST(Frustum, OrthographicBoxIsTheHandComputedSlab) {
    // Screen quadrant x, y in [50, 100] of 100 px -> NDC [0, 1] -> world [0, 1]; depth 1..10.
    const Frustum f = make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 50, 50, 100, 100);
    EXPECT_TRUE(inside(f, {0.5, 0.5, -5}));
    EXPECT_FALSE(inside(f, {-0.01, 0.5, -5}));
    EXPECT_FALSE(inside(f, {0.5, 1.01, -5}));
    EXPECT_FALSE(inside(f, {0.5, 0.5, -0.99}));
    EXPECT_FALSE(inside(f, {0.5, 0.5, -10.01}));
    EXPECT_NEAR(f.planes[0].distance({0.25, 0.5, -5}), 0.25, 1e-12);  // unit normals: metres
}

TEST(Frustum, PerspectiveBoxWidensWithDepth) {
    const Matrix4 projection = perspective(kPi / 2, 1, 1, 100);  // 90°: half width = depth
    const Frustum full = make_screen_frustum(kIdentity, projection, 200, 200, 0, 0, 200, 200);
    EXPECT_TRUE(inside(full, {1.9, 0, -2}));
    EXPECT_FALSE(inside(full, {2.1, 0, -2}));
    EXPECT_TRUE(inside(full, {9.9, -9.9, -10}));
    EXPECT_FALSE(inside(full, {0, 0, 2}));  // behind the camera
    const Frustum right_half = make_screen_frustum(kIdentity, projection, 200, 200, 100, 0, 200, 200);
    EXPECT_FALSE(inside(right_half, {-0.1, 0, -2}));
    EXPECT_TRUE(inside(right_half, {0.1, 0, -2}));
    // The camera moved back 5 m: the world origin is 5 m in front of it.
    const Frustum moved = make_screen_frustum(translation({0, 0, -5}), projection, 200, 200, 100, 100, 200, 200);
    EXPECT_TRUE(inside(moved, {1, 1, 0}));
    EXPECT_FALSE(inside(moved, {-1, 1, 0}));
    EXPECT_FALSE(inside(moved, {5.1, 1, 0}));
}

TEST(Frustum, DegenerateBoxesAndCamerasAreRefused) {
    EXPECT_THROW(make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 10, 10, 10, 50),
                 std::invalid_argument);
    EXPECT_THROW(make_screen_frustum(kIdentity, Matrix4{}, 100, 100, 0, 0, 10, 10), std::invalid_argument);
    EXPECT_THROW(make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 0, 100, 0, 0, 10, 10),
                 std::invalid_argument);
}

TEST(Frustum, SegmentsCountWhenTheyCrossBetweenSamples) {
    const Frustum f = make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 50, 50, 100, 100);
    EXPECT_TRUE(f.touches_segment({-3, 0.5, -5}, {3, 0.5, -5}, 0, 1));   // both ends outside, crosses
    EXPECT_FALSE(f.touches_segment({-3, 0.5, -5}, {3, 0.5, -5}, 0, 0.4));  // the crossing part excluded
    EXPECT_FALSE(f.touches_segment({-1, 0.5, -5}, {0.5, 2.5, -5}, 0, 1));  // passes outside the corner
    EXPECT_TRUE(f.touches_segment({-1, 1, -5}, {3, 1, -5}, 0, 1));       // runs along the top face
    EXPECT_TRUE(f.touches_segment({-1, -0.01, -5}, {1, 1.99, -5}, 0, 1));  // cuts the corner (0, 1)
    EXPECT_FALSE(f.touches_segment({-1, 0.01, -5}, {1, 2.01, -5}, 0, 1));  // passes it 7 mm outside
    EXPECT_TRUE(f.touches_segment({-0.3, 0.5, -5}, {-0.3, 0.6, -5}, 0, 1, 0.31));  // swept radius reaches in
    EXPECT_FALSE(f.touches_segment({-0.3, 0.5, -5}, {-0.3, 0.6, -5}, 0, 1, 0.29));
}

TEST(Frustum, BoxClassification) {
    const Frustum f = make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 50, 50, 100, 100);
    const std::array<Vec3, 3> aligned{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    EXPECT_EQ(f.classify_box({0.5, 0.5, -5}, aligned, {0.2, 0.2, 0.2}, 0), 1);
    EXPECT_EQ(f.classify_box({3, 0.5, -5}, aligned, {0.2, 0.2, 0.2}, 0), -1);
    EXPECT_EQ(f.classify_box({1.1, 0.5, -5}, aligned, {0.2, 0.2, 0.2}, 0), 0);
    EXPECT_EQ(f.classify_box({1.3, 0.5, -5}, aligned, {0.2, 0.2, 0.2}, 0), -1);
    EXPECT_EQ(f.classify_box({1.3, 0.5, -5}, aligned, {0.2, 0.2, 0.2}, 0.11), 0);  // grown by the radius
    const double h = std::sqrt(0.5);
    const std::array<Vec3, 3> turned{Vec3{h, h, 0}, Vec3{-h, h, 0}, Vec3{0, 0, 1}};
    EXPECT_EQ(f.classify_box({1.1, 0.5, -5}, turned, {0.1, 0.1, 0.1}, 0), 0);     // a corner reaches x = 0.96
    EXPECT_EQ(f.classify_box({1.1, 0.5, -5}, turned, {0.06, 0.06, 0.06}, 0), -1);  // x >= 1.015: outside
}

// A random walk of n points (flat, float32) starting in front of the identity camera.
std::vector<float> random_walk(PortableRandom& random, size_t n, double step) {
    std::vector<float> points;
    Vec3 p{random.uniform(-3, 3), random.uniform(-3, 3), random.uniform(-8, -2)};
    for (size_t k = 0; k < n; ++k) {
        for (int a = 0; a < 3; ++a) p[a] += random.uniform(-step, step);
        points.insert(points.end(), {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
    }
    return points;
}

// A random screen rectangle of a 1000 px view through the identity camera, orthographic or not.
Frustum random_screen_box(PortableRandom& random) {
    const bool ortho = random.uniform01() < 0.5;
    const Matrix4 projection = ortho ? orthographic(-4, 4, -4, 4, 0.5, 20) : perspective(1.2, 1.0, 0.5, 20);
    const double x0 = random.uniform(0, 900), y0 = random.uniform(0, 900);
    const double width = random.uniform(5, 400), height = random.uniform(5, 400);
    return make_screen_frustum(kIdentity, projection, 1000, 1000, x0, y0, x0 + width, y0 + height);
}

// Random walks and random boxes: the tree must give exactly the brute-force answer.
TEST(PathTree, TreeAnswersEqualBruteForceOnRandomPathsAndBoxes) {
    PortableRandom random(1234);
    int positives = 0, total = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const size_t n = 1 + static_cast<size_t>(random.uniform(0, 300));
        const std::vector<float> points = random_walk(random, n, 0.15);
        // Half the paths end early and hold their last pose up to a later end of the run.
        const double path_end_s = 4.0 * (n - 1) / 120;
        const double hold_until_s = random.uniform01() < 0.5 ? path_end_s + random.uniform(0, 6) : 0.0;
        const PathTree tree(points, 4, static_cast<uint32_t>(4 * (n - 1)), 120, hold_until_s);
        for (int b = 0; b < 25; ++b) {
            const Frustum f = random_screen_box(random);
            TimeWindow window;
            if (random.uniform01() < 0.3) {
                const double t0 = random.uniform(0, 10);
                window = {t0, t0 + random.uniform(0, 3)};
            }
            const double radius = random.uniform01() < 0.3 ? random.uniform(0, 0.5) : 0.0;
            const bool fast = tree.touches(f, window, radius);
            ASSERT_EQ(fast, tree.touches_brute_force(f, window, radius)) << "trial " << trial << " box " << b;
            positives += fast;
            ++total;
        }
    }
    EXPECT_GT(positives, total / 10) << "the property test must exercise both answers";
    EXPECT_LT(positives, total * 9 / 10);
}

TEST(PathTree, TimeWindowSelectsWhenThePathIsInside) {
    // Along x at 1 m/s: inside the box x in [0, 1] between t = 5 s and t = 6 s.
    std::vector<float> points;
    for (int k = 0; k <= 300; ++k) points.insert(points.end(), {static_cast<float>(-5 + k / 30.0), 0.5f, -5.0f});
    const PathTree tree(points, 4, 1200, 120);
    const Frustum f = make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 50, 50, 100, 100);
    EXPECT_TRUE(tree.touches(f, {}, 0));
    EXPECT_FALSE(tree.touches(f, {0, 4.9}, 0));
    EXPECT_TRUE(tree.touches(f, {5.5, 5.6}, 0));
    EXPECT_FALSE(tree.touches(f, {6.1, 10}, 0));
    EXPECT_NEAR(tree.first_time_inside(f), 5.0, 1e-6);
}

// Along x at 1 m/s from x = -2 until it rests inside the box x in [0, 1] at x = 0.5 (t = 2.5 s);
// the run ends at 8 s.
PathTree path_resting_in_box(double hold_until_s) {
    std::vector<float> points;
    for (int k = 0; k <= 75; ++k) points.insert(points.end(), {static_cast<float>(-2 + k / 30.0), 0.5f, -5.0f});
    return PathTree(points, 4, 300, 120, hold_until_s);
}

TEST(PathTree, AWorldAtRestHoldsItsLastPoseUpToTheRunsEnd) {
    const Frustum box = make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 50, 50, 100, 100);
    const PathTree held = path_resting_in_box(8.0);
    EXPECT_DOUBLE_EQ(held.end_time_s(), 8.0);
    for (const PathTree* tree : {&held}) {
        EXPECT_TRUE(tree->touches(box, {5, 6}, 0)) << "the body rests in the box during the last seconds";
        EXPECT_TRUE(tree->touches_brute_force(box, {5, 6}, 0));
        EXPECT_TRUE(tree->touches(box, {8, 8}, 0));
        EXPECT_TRUE(tree->touches(box, {7.5, 12}, 0));
        EXPECT_TRUE(tree->touches(box, {5, 6}, 0.2)) << "swept";
        EXPECT_FALSE(tree->touches(box, {8.01, 12}, 0)) << "nothing is posed after the run's end";
        EXPECT_FALSE(tree->touches_brute_force(box, {8.01, 12}, 0));
        EXPECT_FALSE(tree->touches(box, {0, 1.9}, 0)) << "before it arrives";
    }
    // The same box one metre to the left: the body left it at t = 1 s and never comes back.
    const Frustum left = make_screen_frustum(kIdentity, orthographic(-1, 1, -1, 1, 1, 10), 100, 100, 0, 50, 50, 100);
    EXPECT_TRUE(held.touches(left, {0, 2}, 0));
    EXPECT_FALSE(held.touches(left, {5, 6}, 0));
    EXPECT_FALSE(held.touches_brute_force(left, {5, 6}, 0));
    // A run shortened to the world's own end (duration): no pose after it.
    const PathTree shortened = path_resting_in_box(0);
    EXPECT_DOUBLE_EQ(shortened.end_time_s(), 2.5);
    EXPECT_FALSE(shortened.touches(box, {5, 6}, 0));
    EXPECT_TRUE(shortened.touches(box, {2.5, 6}, 0));
}

// A synthetic index: world w has body 0 passing through x = w and body 1 resting at the origin.
void fill_small_index(PathIndex& index, int worlds) {
    std::vector<IndexedWorldInput> inputs;
    for (int w = 0; w < worlds; ++w) {
        IndexedWorldInput in;
        in.world_index = static_cast<uint64_t>(w);
        in.last_frame = 400;
        std::vector<float> moving, resting;
        for (int k = 0; k <= 100; ++k) {
            moving.insert(moving.end(), {static_cast<float>(w) + 0.5f, static_cast<float>(-5 + k * 0.1), -5.0f});
            resting.insert(resting.end(), {-20.0f, 0.0f, -5.0f});
        }
        in.polylines = {moving, resting};
        in.final_orientations = {Quat{1, 0, 0, 0}, quat_from_axis_angle({0, 0, 1}, 0.1 * w)};
        in.metric_names = {"collision_count", "time_to_rest_s"};
        in.metric_values = {{double(w % 3), 1.0}, {10.0 - w, double(w)}};
        inputs.push_back(std::move(in));
    }
    index.add_worlds(std::move(inputs), 2);
}

QueryBox box_over_x(double x0, double x1, bool negative, std::vector<uint32_t> bodies) {
    // Orthographic camera over x in [-10, 10] on a 2000 px screen: 100 px per metre.
    QueryBox box;
    box.frustum = make_screen_frustum(kIdentity, orthographic(-10, 10, -10, 10, 1, 10), 2000, 2000,
                                      (x0 + 10) * 100, 0, (x1 + 10) * 100, 2000);
    box.negative = negative;
    box.bodies = std::move(bodies);
    return box;
}

// Random worlds (some without some bodies) and random sets of boxes (positive and negative, time
// windows, swept): the index's per-world count of boxes met must be exactly brute force's.
TEST(PathIndex, IndexAnswersEqualBruteForceOnRandomWorldsAndBoxes) {
    PortableRandom random(4321);
    constexpr uint32_t kBodies = 6;
    std::vector<IndexedWorldInput> worlds(120);
    for (size_t w = 0; w < worlds.size(); ++w) {
        IndexedWorldInput& world = worlds[w];
        world.world_index = 3 * w + 1;
        const size_t n = 2 + static_cast<size_t>(random.uniform(0, 120));
        world.last_frame = static_cast<uint32_t>(4 * (n - 1));
        world.hold_until_s = random.uniform01() < 0.5 ? 4.0 * (n - 1) / 120 + random.uniform(0, 4) : 0.0;
        // A world made before the last bodies were added has fewer paths; a removed body has none.
        const uint32_t paths = random.uniform01() < 0.2 ? kBodies - 2 : kBodies;
        for (uint32_t b = 0; b < paths; ++b) {
            world.polylines.push_back(random.uniform01() < 0.1 ? std::vector<float>{} : random_walk(random, n, 0.2));
            world.final_orientations.push_back({1, 0, 0, 0});
        }
    }
    PathIndex index(std::vector<double>(kBodies, 0.3));
    index.add_worlds(std::move(worlds), 2);
    size_t met = 0, counted = 0;
    for (int trial = 0; trial < 150; ++trial) {
        std::vector<QueryBox> boxes(1 + static_cast<size_t>(random.uniform(0, 3)));
        for (QueryBox& box : boxes) {
            box.frustum = random_screen_box(random);
            box.negative = random.uniform01() < 0.4;
            box.swept = random.uniform01() < 0.3;
            for (uint32_t b = 0; b < kBodies; ++b)
                if (random.uniform01() < 0.5) box.bodies.push_back(b);
            if (random.uniform01() < 0.3) {
                const double t0 = random.uniform(0, 4);
                box.window = {t0, t0 + random.uniform(0, 2)};
            }
        }
        const QueryResult fast = index.query(boxes, 0, false);
        const QueryResult brute = index.query(boxes, 0, true);
        ASSERT_EQ(fast.boxes_satisfied, brute.boxes_satisfied) << "trial " << trial;
        ASSERT_EQ(fast.matching, brute.matching) << "trial " << trial;
        for (uint32_t n : fast.boxes_satisfied) met += n;
        counted += fast.boxes_satisfied.size() * boxes.size();
    }
    // Both answers must be common for the comparison to mean anything.
    EXPECT_GT(met, counted / 10);
    EXPECT_LT(met, counted * 9 / 10);
}

TEST(PathIndex, PositiveAndNegativeBoxesCombineByAnd) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 6);
    const QueryResult keep = index.query({box_over_x(2, 4, false, {0})});
    EXPECT_EQ(keep.matching, (std::vector<uint64_t>{2, 3}));
    const QueryResult both = index.query({box_over_x(2, 4, false, {0}), box_over_x(3, 10, true, {0})});
    EXPECT_EQ(both.matching, (std::vector<uint64_t>{2}));
    EXPECT_EQ(both.boxes_satisfied, (std::vector<uint32_t>{1, 1, 2, 1, 0, 0}));
    // A box over the resting body's spot: only body 1 enters it, in every world.
    EXPECT_EQ(index.query({box_over_x(-21, -19, false, {0})}).matching.size(), 0u);
    EXPECT_EQ(index.query({box_over_x(-21, -19, false, {0, 1})}).matching.size(), 6u);
}

TEST(PathIndex, BoxesMetRanksEveryWorldByTheBoxesItsQueryCounts) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 6);
    const std::vector<QueryBox> boxes{box_over_x(2, 4, false, {0}), box_over_x(3, 10, true, {0})};
    // Counts 1, 1, 2, 1, 0, 0 (as the test above): most first, ties in world order.
    const auto most = index.rank("boxes_met", {}, Combine::Sum, true, nullptr, nullptr, &boxes);
    EXPECT_EQ(most, (std::vector<std::pair<uint64_t, double>>{{2, 2.0}, {0, 1.0}, {1, 1.0}, {3, 1.0}, {4, 0.0}, {5, 0.0}}));
    const std::vector<uint64_t> only{3, 4};
    const auto fewest = index.rank("boxes_met", {}, Combine::Sum, false, &only, nullptr, &boxes);
    EXPECT_EQ(fewest, (std::vector<std::pair<uint64_t, double>>{{4, 0.0}, {3, 1.0}}));
    EXPECT_THROW(index.rank("boxes_met", {}, Combine::Sum, true), std::invalid_argument);
}

TEST(PathIndex, SweptQueriesSeeTheWholeBody) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 3);
    // Body 0 (radius 0.1 m) runs along x = 1.5 in world 1 and x = 2.5 in world 2. A box from
    // x = 1.65 is 0.15 m from world 1's path: out of reach either way.
    QueryBox box = box_over_x(1.65, 3, false, {0});
    EXPECT_EQ(index.query({box}).matching, (std::vector<uint64_t>{2}));
    box.swept = true;
    EXPECT_EQ(index.query({box}).matching, (std::vector<uint64_t>{2}));
    box = box_over_x(1.55, 3, false, {0});
    EXPECT_EQ(index.query({box}).matching, (std::vector<uint64_t>{2}));
    box.swept = true;  // 0.05 m from the path: the 0.1 m body touches
    EXPECT_EQ(index.query({box}).matching, (std::vector<uint64_t>{1, 2}));
}

TEST(PathIndex, WorldsThatEndedEarlyAreSeenAtRestByTimeWindows) {
    // World w: body 0 slides along x and stops at x = 0.5 after 1 + w seconds; the
    // run ends at 6 s. Only world 5 runs to the end.
    PathIndex index({0.1});
    std::vector<IndexedWorldInput> inputs;
    for (int w = 0; w < 6; ++w) {
        IndexedWorldInput in;
        in.world_index = static_cast<uint64_t>(w);
        in.stride = 1;
        in.record_hz = 10;
        in.hold_until_s = 6;
        const int frames = 10 * (1 + w) + 1;
        in.last_frame = static_cast<uint32_t>(frames - 1);
        std::vector<float> path;
        for (int k = 0; k < frames; ++k)
            path.insert(path.end(), {static_cast<float>(-5 + 5.5 * k / (frames - 1)), 0.0f, -5.0f});
        in.polylines = {path};
        in.final_orientations = {Quat{1, 0, 0, 0}};
        inputs.push_back(std::move(in));
    }
    index.add_worlds(std::move(inputs), 2);
    for (const bool swept : {false, true}) {
        for (const bool brute_force : {false, true}) {
            QueryBox rest_place = box_over_x(0, 1, false, {0});
            rest_place.window = {5, 6};
            rest_place.swept = swept;
            EXPECT_EQ(index.query({rest_place}, 0, brute_force).matching.size(), 6u)
                << "every world rests in the box in the last second, whenever it ended";
            rest_place.negative = true;
            EXPECT_EQ(index.query({rest_place}, 0, brute_force).matching.size(), 0u)
                << "a negative box over the resting place rejects every world";
            QueryBox elsewhere = box_over_x(3, 4, true, {0});
            elsewhere.window = {5, 6};
            elsewhere.swept = swept;
            EXPECT_EQ(index.query({elsewhere}, 0, brute_force).matching.size(), 6u);
        }
    }
}

TEST(PathIndex, QueriesGiveTheSameAnswerOnOneAndTwoThreads) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 300);  // worlds 0..299 move along x = w + 0.5
    QueryBox ordered = box_over_x(-21, -19, false, {1});
    ordered.after = 0;
    for (const std::vector<QueryBox>& boxes :
         {std::vector<QueryBox>{box_over_x(2, 9, false, {0}), box_over_x(5, 6, true, {0})},
          std::vector<QueryBox>{box_over_x(100, 120, false, {0}), ordered}}) {
        const QueryResult one = index.query(boxes, 0, false, 1);
        const QueryResult two = index.query(boxes, 0, false, 2);
        EXPECT_EQ(one.world_indices, two.world_indices);
        EXPECT_EQ(one.boxes_satisfied, two.boxes_satisfied);
        EXPECT_EQ(one.matching, two.matching);
        EXPECT_FALSE(one.matching.empty());
    }
    EXPECT_EQ(index.query({box_over_x(2, 9, false, {0}), box_over_x(5, 6, true, {0})}, 0, false, 2).matching,
              (std::vector<uint64_t>{2, 3, 4, 6, 7, 8}));
    // Rankings too: collision_count of body 0 is w % 3, so ties abound and must keep world order.
    omp_set_num_threads(1);
    const auto ranked_one = index.rank("collision_count", {0}, Combine::Sum, true);
    omp_set_num_threads(2);
    const auto ranked_two = index.rank("collision_count", {0}, Combine::Sum, true);
    EXPECT_EQ(ranked_one, ranked_two);
    ASSERT_EQ(ranked_two.size(), 300u);
    EXPECT_EQ(ranked_two[0], std::make_pair(uint64_t{2}, 2.0));
    EXPECT_EQ(ranked_two[1], std::make_pair(uint64_t{5}, 2.0));
}

TEST(PathIndex, ANewerQuerySupersedesARunningOne) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 200);
    index.post_generation(7);
    const QueryResult stale = index.query({box_over_x(2, 4, false, {0})}, 6);
    EXPECT_TRUE(stale.superseded);
    const QueryResult current = index.query({box_over_x(2, 4, false, {0})}, 7);
    EXPECT_FALSE(current.superseded);
    EXPECT_EQ(current.world_indices.size(), 200u);
}

TEST(PathIndex, RankingCombinesBodiesBySumOrMax) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 6);
    const auto by_sum = index.rank("time_to_rest_s", {0, 1}, Combine::Sum, false);
    // time_to_rest: body 0 = 10 - w, body 1 = w: the sum is 10 for every world; ties keep order.
    for (size_t k = 0; k < by_sum.size(); ++k) EXPECT_EQ(by_sum[k], std::make_pair(uint64_t(k), 10.0));
    const auto by_max = index.rank("time_to_rest_s", {0, 1}, Combine::Max, true);
    EXPECT_EQ(by_max.front(), std::make_pair(uint64_t{0}, 10.0));
    EXPECT_EQ(by_max.back(), std::make_pair(uint64_t{5}, 5.0));
    const std::vector<uint64_t> only{1, 4};
    const auto subset = index.rank("collision_count", {0}, Combine::Sum, true, &only);
    EXPECT_EQ(subset, (std::vector<std::pair<uint64_t, double>>{{1, 1.0}, {4, 1.0}}));  // a tie keeps world order
    const std::vector<Quat> goal{quat_from_axis_angle({0, 0, 1}, 0.3)};
    const auto to_goal = index.rank("orientation_to_goal_rad", {1}, Combine::Sum, false, nullptr, &goal);
    EXPECT_EQ(to_goal.front().first, 3u);
    EXPECT_NEAR(to_goal.front().second, 0.0, 1e-6);
    EXPECT_THROW(index.rank("no_such_metric", {0}, Combine::Sum, false), std::invalid_argument);
}

// Bodies added to or removed from worlds after sampling: a world without a body has no path for it.
TEST(PathIndex, WorldsAreRankedOverTheBodiesTheyHave) {
    PathIndex index({0.1, 0.5});
    fill_small_index(index, 3);
    std::vector<IndexedWorldInput> lacking;
    for (uint64_t w : {10, 11}) {
        IndexedWorldInput in;
        in.world_index = w;
        in.last_frame = 400;
        in.polylines = {std::vector<float>{}};  // body 0 removed; body 1 added later than this world
        if (w == 11) in.polylines[0] = {0.5f, 0.0f, -5.0f};
        in.final_orientations = {Quat{1, 0, 0, 0}};
        in.metric_names = {"collision_count", "time_to_rest_s"};
        in.metric_values = {{0.0}, {w == 11 ? 4.0 : 0.0}};
        lacking.push_back(std::move(in));
    }
    index.add_worlds(std::move(lacking), 1);
    const auto by_sum = index.rank("time_to_rest_s", {0, 1}, Combine::Sum, false);
    EXPECT_EQ(by_sum, (std::vector<std::pair<uint64_t, double>>{{11, 4.0}, {0, 10.0}, {1, 10.0}, {2, 10.0}}))
        << "world 11 over body 0 alone; world 10 has neither body and is left out";
    const auto by_max = index.rank("time_to_rest_s", {1}, Combine::Max, false);
    EXPECT_EQ(by_max.size(), 3u);
    EXPECT_EQ(index.query({box_over_x(-21, -19, false, {1})}).matching, (std::vector<uint64_t>{0, 1, 2}));
    EXPECT_EQ(index.query({box_over_x(-21, -19, true, {1})}).matching, (std::vector<uint64_t>{10, 11}));
}

TEST(PathIndex, QueriesRunWhileWorldsAreAdded) {
    PathIndex index({0.1, 0.5});
    std::thread writer([&] {
        for (int w = 0; w < 40; ++w) {
            IndexedWorldInput in;
            in.world_index = static_cast<uint64_t>(w);
            in.last_frame = 4;
            in.polylines = {{0, 0, -5, 1, 0, -5}, {0, 0, -5}};
            in.final_orientations = {Quat{1, 0, 0, 0}, Quat{1, 0, 0, 0}};
            std::vector<IndexedWorldInput> one;
            one.push_back(std::move(in));
            index.add_worlds(std::move(one), 1);
        }
    });
    size_t last = 0;
    while (last < 40) {
        const size_t now = index.query({box_over_x(-1, 1, false, {0})}).matching.size();
        EXPECT_GE(now, last);
        last = now;
    }
    writer.join();
}

}  // namespace
}  // namespace mwb

namespace mwb {
namespace {

TEST(RankingMetrics, TheCatalogStartsWithTheStoredMetricsAndNamesEachOnce) {
    const std::vector<RankingMetric>& metrics = ranking_metrics();
    const std::vector<std::string>& stored = stored_metric_names();
    ASSERT_GT(metrics.size(), stored.size());
    for (size_t k = 0; k < stored.size(); ++k) EXPECT_EQ(metrics[k].name, stored[k]);
    std::set<std::string> names;
    for (const RankingMetric& m : metrics) {
        EXPECT_TRUE(names.insert(m.name).second) << m.name;
        EXPECT_TRUE(std::set<std::string>({"rad", "s", "m", "hits", "parts"}).count(m.unit)) << m.name << " " << m.unit;
        EXPECT_FALSE(m.label.empty() || m.help.empty()) << m.name;
    }
    EXPECT_TRUE(names.count("boxes_met") && names.count("orientation_to_goal_rad"));
}

}  // namespace
}  // namespace mwb
