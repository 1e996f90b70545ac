#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "geometry/ConvexHull.h"

namespace mwb {
namespace {

void push(std::vector<double>& xyz, const Vec3& p) { xyz.insert(xyz.end(), p.begin(), p.end()); }

std::vector<double> cube_corners(double half, const Vec3& center = {0, 0, 0}) {
    std::vector<double> xyz;
    for (int i = 0; i < 8; ++i)
        push(xyz, add(center, {i & 1 ? half : -half, i & 2 ? half : -half, i & 4 ? half : -half}));
    return xyz;
}

// Newell's normal of a face as listed: points outward when the face is counter-clockwise.
Vec3 winding_normal(const ConvexHull& hull, const std::vector<uint32_t>& face) {
    Vec3 n{0, 0, 0};
    for (size_t i = 0; i < face.size(); ++i) {
        const Vec3& a = hull.points[face[i]];
        const Vec3& b = hull.points[face[(i + 1) % face.size()]];
        n = add(n, cross(a, b));
    }
    return n;
}

// Planes are unit, faces are CCW from outside and lie on their planes, every point is inside
// every plane, and the polygons close up into a sphere (V - E + F = 2).
void expect_well_formed(const ConvexHull& hull, double tolerance) {
    ASSERT_EQ(hull.planes.size(), hull.faces.size());
    std::set<std::pair<uint32_t, uint32_t>> edges;
    for (size_t f = 0; f < hull.faces.size(); ++f) {
        const Vec3 n{hull.planes[f][0], hull.planes[f][1], hull.planes[f][2]};
        EXPECT_NEAR(norm(n), 1.0, 1e-12);
        EXPECT_GT(dot(winding_normal(hull, hull.faces[f]), n), 0) << "face " << f << " is not CCW from outside";
        ASSERT_GE(hull.faces[f].size(), 3u);
        for (size_t i = 0; i < hull.faces[f].size(); ++i) {
            const uint32_t a = hull.faces[f][i], b = hull.faces[f][(i + 1) % hull.faces[f].size()];
            ASSERT_LT(a, hull.points.size());
            EXPECT_NEAR(dot(n, hull.points[a]), hull.planes[f][3], tolerance);
            EXPECT_TRUE(edges.emplace(a, b).second) << "directed edge used twice";
        }
        for (const Vec3& p : hull.points) EXPECT_LE(dot(n, p) - hull.planes[f][3], tolerance);
    }
    for (const auto& [a, b] : edges) EXPECT_TRUE(edges.count({b, a})) << "open edge " << a << "-" << b;
    const long euler = static_cast<long>(hull.points.size()) - static_cast<long>(edges.size() / 2) +
                       static_cast<long>(hull.faces.size());
    EXPECT_EQ(euler, 2);
}

TEST(ConvexHull, CubeWithInteriorAndDuplicatePointsHasEightCornersAndSixQuads) {
    std::vector<double> xyz = cube_corners(1.0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> inside(-0.99, 0.99);
    for (int i = 0; i < 200; ++i) push(xyz, {inside(rng), inside(rng), inside(rng)});
    push(xyz, {1, 1, 1});      // duplicate corner
    push(xyz, {1, 0.3, -0.2});  // on a face
    push(xyz, {1, 1, 0.5});     // on an edge
    const ConvexHull hull = compute_convex_hull(xyz);

    EXPECT_EQ(hull.points.size(), 8u);
    for (const Vec3& p : hull.points)
        for (double c : p) EXPECT_EQ(std::fabs(c), 1.0);
    ASSERT_EQ(hull.faces.size(), 6u);
    std::set<std::array<double, 4>> planes(hull.planes.begin(), hull.planes.end());
    for (int axis = 0; axis < 3; ++axis) {
        for (double sign : {-1.0, 1.0}) {
            std::array<double, 4> plane{0, 0, 0, 1};
            plane[axis] = sign;
            EXPECT_TRUE(planes.count(plane)) << "missing plane on axis " << axis << " sign " << sign;
        }
    }
    for (const auto& face : hull.faces) EXPECT_EQ(face.size(), 4u);
    expect_well_formed(hull, 1e-12);
}

TEST(ConvexHull, RandomPointsOnASphereAreAllOnTheHull) {
    std::mt19937 rng(12345);
    std::normal_distribution<double> gauss;
    std::vector<double> xyz;
    for (int i = 0; i < 500; ++i) {
        const Vec3 p{gauss(rng), gauss(rng), gauss(rng)};
        push(xyz, scale(p, 2.5 / norm(p)));
    }
    const ConvexHull hull = compute_convex_hull(xyz);
    EXPECT_EQ(hull.points.size(), 500u);
    EXPECT_EQ(hull.faces.size(), 2 * 500u - 4);  // a triangulated sphere, nothing coplanar
    expect_well_formed(hull, 1e-9);
    for (size_t i = 0; i < xyz.size(); i += 3)
        for (const auto& plane : hull.planes)
            EXPECT_LE(plane[0] * xyz[i] + plane[1] * xyz[i + 1] + plane[2] * xyz[i + 2] - plane[3], 1e-9);
}

TEST(ConvexHull, ToleranceFollowsTheExtentNotTheDistanceFromTheOrigin) {
    std::vector<double> xyz = cube_corners(1e-3, {1e4, -2e4, 3e4});
    push(xyz, {1e4, -2e4, 3e4});
    const ConvexHull hull = compute_convex_hull(xyz);
    EXPECT_EQ(hull.points.size(), 8u);
    EXPECT_EQ(hull.faces.size(), 6u);
    expect_well_formed(hull, 1e-9);
}

TEST(ConvexHull, TetrahedronAndSquarePyramid) {
    const ConvexHull tetra = compute_convex_hull({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
    EXPECT_EQ(tetra.points.size(), 4u);
    EXPECT_EQ(tetra.faces.size(), 4u);
    expect_well_formed(tetra, 1e-12);

    const ConvexHull pyramid = compute_convex_hull({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 2});
    EXPECT_EQ(pyramid.faces.size(), 5u);
    std::map<size_t, int> sizes;
    for (const auto& face : pyramid.faces) ++sizes[face.size()];
    EXPECT_EQ(sizes[4], 1);
    EXPECT_EQ(sizes[3], 4);
    expect_well_formed(pyramid, 1e-12);
}

TEST(ConvexHull, LatticesFullOfCoplanarAndCollinearPointsStayWellFormed) {
    std::vector<double> grid;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 5; ++k) push(grid, {i * 0.25, j * 0.25, k * 0.25});
    const ConvexHull cube = compute_convex_hull(grid);
    EXPECT_EQ(cube.points.size(), 8u);
    EXPECT_EQ(cube.faces.size(), 6u);
    expect_well_formed(cube, 1e-12);

    // Few distinct integer coordinates: many exact ties, duplicates and coplanar faces.
    std::mt19937 rng(99);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<double> xyz;
        const int count = 4 + static_cast<int>(rng() % 40);
        for (int i = 0; i < count; ++i)
            push(xyz, {static_cast<double>(rng() % 4), static_cast<double>(rng() % 4), static_cast<double>(rng() % 3)});
        try {
            expect_well_formed(compute_convex_hull(xyz), 1e-12);
        } catch (const GeometryError&) {
            // Flat or collinear draws are allowed to be refused.
        }
    }
}

TEST(ConvexHull, DegenerateInputsThrow) {
    EXPECT_THROW(compute_convex_hull({}), GeometryError);
    EXPECT_THROW(compute_convex_hull({0, 0, 0, 1, 0, 0, 0, 1, 0}), GeometryError);           // 3 points
    EXPECT_THROW(compute_convex_hull({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}), GeometryError);     // not (n, 3)
    EXPECT_THROW(compute_convex_hull(std::vector<double>(30, 2.0)), GeometryError);          // coincident
    EXPECT_THROW(compute_convex_hull({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, -1, -1, -1}), GeometryError);  // collinear
    std::vector<double> plane;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) push(plane, {static_cast<double>(i), static_cast<double>(j), 0.5 * i - 0.25 * j});
    EXPECT_THROW(compute_convex_hull(plane), GeometryError);  // coplanar, tilted
    std::vector<double> with_nan = cube_corners(1.0);
    with_nan[4] = std::nan("");
    EXPECT_THROW(compute_convex_hull(with_nan), GeometryError);
}

}  // namespace
}  // namespace mwb

namespace mwb {
namespace {

// The unit cube's 8 corners and its 12 triangles (outward), face by face: -z, +z, -y, +y, -x, +x.
const std::vector<double> kCubeCorners{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
const std::vector<uint32_t> kCubeTriangles{0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                           3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

TEST(MeshFillsItsHull, ClosedConvexMeshesAndWholePlanesDo) {
    EXPECT_TRUE(mesh_fills_its_hull(kCubeCorners, kCubeTriangles));
    const std::vector<double> plane{-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0};
    EXPECT_TRUE(mesh_fills_its_hull(plane, {0, 1, 2, 0, 2, 3}));
}

TEST(MeshFillsItsHull, OpenConcaveNotchedOrDoubledMeshesDoNot) {
    // A bin: the cube without its top face must stay hollow.
    std::vector<uint32_t> open(kCubeTriangles.begin(), kCubeTriangles.end());
    open.erase(open.begin() + 6, open.begin() + 12);
    EXPECT_FALSE(mesh_fills_its_hull(kCubeCorners, open));
    // An L-shaped floor: its hull would fill the notch.
    const std::vector<double> l_floor{0, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, 1, 2, 0, 0, 2, 0};
    EXPECT_FALSE(mesh_fills_its_hull(l_floor, {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5}));
    // A plane whose triangles are there twice (both sides modelled).
    const std::vector<double> plane{-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0};
    EXPECT_FALSE(mesh_fills_its_hull(plane, {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2}));
    // A cube with a dent: one corner pushed in.
    std::vector<double> dented = kCubeCorners;
    dented[18] = dented[19] = dented[20] = 0.8;
    EXPECT_FALSE(mesh_fills_its_hull(dented, kCubeTriangles));
}

}  // namespace
}  // namespace mwb
