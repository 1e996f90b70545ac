#include <gtest/gtest.h>

#include "geometry/ConvexHull.h"
#include "geometry/MassProperties.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;

Shape box_shape(const Vec3& half) {
    Shape s;
    s.type = ShapeType::Box;
    s.half_extents_m = half;
    return s;
}

Shape round_shape(ShapeType type, double radius, double height) {
    Shape s;
    s.type = type;
    s.radius_m = radius;
    s.height_m = height;
    return s;
}

// The 8 corners of an axis-aligned box and its 12 outward-wound triangles.
Shape box_mesh(const Vec3& half, ShapeType type) {
    Shape s;
    s.type = type;
    for (int i = 0; i < 8; ++i)
        s.vertices_m.insert(s.vertices_m.end(), {i & 1 ? half[0] : -half[0], i & 2 ? half[1] : -half[1],
                                                 i & 4 ? half[2] : -half[2]});
    s.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                   2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    return s;
}

void expect_diagonal(const MassProperties& p, double ixx, double iyy, double izz, double tol) {
    const std::array<double, 9> expected{ixx, 0, 0, 0, iyy, 0, 0, 0, izz};
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(p.inertia[k], expected[k], tol) << "inertia[" << k << "]";
}

void expect_same(const MassProperties& a, const MassProperties& b, double tol) {
    EXPECT_NEAR(a.volume_m3, b.volume_m3, tol);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.center_of_mass_m[k], b.center_of_mass_m[k], tol);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(a.inertia[k], b.inertia[k], tol) << "inertia[" << k << "]";
}

TEST(MassProperties, BoxIsMassTimesSumOfSquaredFullExtentsOverTwelve) {
    const double m = 3.0, a = 1.0, b = 2.0, c = 4.0;  // full extents
    const MassProperties p = compute_mass_properties(box_shape({a / 2, b / 2, c / 2}), m);
    EXPECT_DOUBLE_EQ(p.volume_m3, a * b * c);
    EXPECT_EQ(p.center_of_mass_m, (Vec3{0, 0, 0}));
    expect_diagonal(p, m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12, 1e-12);
}

TEST(MassProperties, SphereIsTwoFifthsMRSquared) {
    const MassProperties p = compute_mass_properties(round_shape(ShapeType::Sphere, 0.5, 0), 2.0);
    EXPECT_DOUBLE_EQ(p.volume_m3, 4.0 / 3.0 * kPi * 0.125);
    expect_diagonal(p, 0.2, 0.2, 0.2, 1e-15);
}

TEST(MassProperties, CylinderAlongZ) {
    const double m = 2.0, r = 0.5, h = 3.0;
    const MassProperties p = compute_mass_properties(round_shape(ShapeType::Cylinder, r, h), m);
    EXPECT_DOUBLE_EQ(p.volume_m3, kPi * r * r * h);
    const double side = m * (3 * r * r + h * h) / 12;
    expect_diagonal(p, side, side, m * r * r / 2, 1e-12);
}

TEST(MassProperties, CapsuleIsCylinderPlusTwoHemispheres) {
    const double m = 5.0, r = 0.5, h = 3.0, l = h - 2 * r;
    const MassProperties p = compute_mass_properties(round_shape(ShapeType::Capsule, r, h), m);
    const double vc = kPi * r * r * l, vs = 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_DOUBLE_EQ(p.volume_m3, vc + vs);
    const double mc = m * vc / (vc + vs), ms = m * vs / (vc + vs);
    // Hemisphere about its own centroid: 83/320 m r²; its centroid sits l/2 + 3r/8 from the centre.
    const double hemi_side = 83.0 / 320.0 * (ms / 2) * r * r + ms / 2 * std::pow(l / 2 + 3 * r / 8, 2);
    const double side = mc * (3 * r * r + l * l) / 12 + 2 * hemi_side;
    expect_diagonal(p, side, side, mc * r * r / 2 + 0.4 * ms * r * r, 1e-12);

    // With no cylinder left the capsule is a sphere.
    const MassProperties ball = compute_mass_properties(round_shape(ShapeType::Capsule, r, 2 * r), m);
    expect_diagonal(ball, 0.4 * m * r * r, 0.4 * m * r * r, 0.4 * m * r * r, 1e-12);
    EXPECT_THROW(compute_mass_properties(round_shape(ShapeType::Capsule, r, 0.9), m), GeometryError);
}

TEST(MassProperties, ConeCentreOfMassIsAQuarterOfTheHeightAboveTheBase) {
    const double m = 4.0, r = 1.0, h = 2.0;
    const MassProperties p = compute_mass_properties(round_shape(ShapeType::Cone, r, h), m);
    EXPECT_DOUBLE_EQ(p.volume_m3, kPi * r * r * h / 3);
    const double base_z = -h / 2;
    EXPECT_DOUBLE_EQ(p.center_of_mass_m[2] - base_z, h / 4);
    const double side = m * (3 * r * r / 20 + 3 * h * h / 80);
    expect_diagonal(p, side, side, 0.3 * m * r * r, 1e-12);
}

TEST(MassProperties, ConvexHullOfABoxEqualsTheBox) {
    const Vec3 half{0.5, 1.0, 2.0};
    Shape hull = box_mesh(half, ShapeType::ConvexHull);
    hull.triangles.clear();
    hull.vertices_m.insert(hull.vertices_m.end(), {0.1, 0.2, 0.3, -0.4, 0.5, 1.9});  // interior points
    expect_same(compute_mass_properties(hull, 7.0), compute_mass_properties(box_shape(half), 7.0), 1e-12);
}

TEST(MassProperties, ConvexHullOfAnOffsetTetrahedron) {
    Shape tetra;
    tetra.type = ShapeType::ConvexHull;
    tetra.vertices_m = {1, 1, 1, 2, 1, 1, 1, 2, 1, 1, 1, 2};
    const MassProperties p = compute_mass_properties(tetra, 1.0);
    EXPECT_NEAR(p.volume_m3, 1.0 / 6.0, 1e-15);
    for (double c : p.center_of_mass_m) EXPECT_NEAR(c, 1.25, 1e-15);
    // Per unit mass a unit right tetrahedron has <x²> = 1/10, <xy> = 1/20 and its centroid at 1/4,
    // so about the centroid Ixx = 2 (1/10 - 1/16) and Ixy = -(1/20 - 1/16).
    const double diag = 2 * (1.0 / 10) - 2 * (1.0 / 16), off = -(1.0 / 20 - 1.0 / 16);
    const std::array<double, 9> expected{diag, off, off, off, diag, off, off, off, diag};
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(p.inertia[k], expected[k], 1e-14) << k;
}

TEST(MassProperties, ClosedMeshBoxEqualsTheBoxInEitherWinding) {
    const Vec3 half{0.25, 0.5, 1.5};
    const MassProperties box = compute_mass_properties(box_shape(half), 2.0);
    Shape mesh = box_mesh(half, ShapeType::Mesh);
    expect_same(compute_mass_properties(mesh, 2.0), box, 1e-12);
    for (size_t t = 0; t < mesh.triangles.size(); t += 3) std::swap(mesh.triangles[t + 1], mesh.triangles[t + 2]);
    expect_same(compute_mass_properties(mesh, 2.0), box, 1e-12);
}

TEST(MassProperties, OpenMeshUsesItsConvexHull) {
    const Vec3 half{0.5, 0.5, 0.5};
    Shape mesh = box_mesh(half, ShapeType::Mesh);
    mesh.triangles.resize(mesh.triangles.size() - 6);  // drop one side
    expect_same(compute_mass_properties(mesh, 1.0), compute_mass_properties(box_shape(half), 1.0), 1e-12);
}

TEST(MassProperties, CompoundSplitsMassByVolumeAndUsesParallelAxes) {
    // Two unit cubes side by side along X, the right one rotated (a cube is symmetric, so the
    // rotation must not change anything): together a 2 x 1 x 1 box centred at x = 0.5.
    Shape compound;
    compound.type = ShapeType::Compound;
    Shape left = box_shape({0.5, 0.5, 0.5});
    Shape right = left;
    right.offset.location = {1, 0, 0};
    right.offset.rotation = quat_from_axis_angle({0, 0, 1}, kPi / 2);
    compound.children = {left, right};
    const MassProperties p = compute_mass_properties(compound, 6.0);
    const MassProperties whole = compute_mass_properties(box_shape({1.0, 0.5, 0.5}), 6.0);
    EXPECT_NEAR(p.volume_m3, 2.0, 1e-15);
    EXPECT_NEAR(p.center_of_mass_m[0], 0.5, 1e-15);
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(p.inertia[k], whole.inertia[k], 1e-12) << k;

    // A big and a small sphere: the centre of mass is the volume-weighted mean of the centres.
    Shape spheres;
    spheres.type = ShapeType::Compound;
    Shape big = round_shape(ShapeType::Sphere, 1.0, 0), small = round_shape(ShapeType::Sphere, 0.5, 0);
    big.offset.location = {0, 0, 1};
    small.offset.location = {0, 3, 1};
    spheres.children = {big, small};
    const MassProperties s = compute_mass_properties(spheres, 9.0);
    EXPECT_NEAR(s.center_of_mass_m[1], 3.0 * 0.125 / 1.125, 1e-14);
    EXPECT_NEAR(s.center_of_mass_m[2], 1.0, 1e-14);
}

TEST(MassProperties, ZeroVolumeThrows) {
    // A flat BOX (Blender's BOX on a plane) is a thin plate, not an error.
    EXPECT_NEAR(compute_mass_properties(box_shape({1, 0, 1}), 3.0).inertia[0], 1.0, 1e-6);
    EXPECT_THROW(compute_mass_properties(round_shape(ShapeType::Sphere, 0, 0), 1.0), GeometryError);
    EXPECT_THROW(compute_mass_properties(round_shape(ShapeType::Cylinder, 1, 0), 1.0), GeometryError);
    Shape flat;
    flat.type = ShapeType::ConvexHull;
    flat.vertices_m = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    // A flat hull (Blender's CONVEX_HULL of a plane) is a 1 mm slab; points on a line are nothing.
    EXPECT_NEAR(compute_mass_properties(flat, 3.0).inertia[8], 3.0 * (1 + 1) / 12, 1e-6);
    flat.vertices_m = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
    EXPECT_THROW(compute_mass_properties(flat, 1.0), GeometryError);
    Shape empty;
    empty.type = ShapeType::Compound;
    EXPECT_THROW(compute_mass_properties(empty, 1.0), GeometryError);
    // A closed but flat (double-sided) mesh encloses nothing.
    Shape sheet;
    sheet.type = ShapeType::Mesh;
    sheet.vertices_m = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    sheet.triangles = {0, 1, 2, 0, 2, 1};
    EXPECT_THROW(compute_mass_properties(sheet, 1.0), GeometryError);
}

}  // namespace
}  // namespace mwb
