#pragma once
// 3D convex hull of a point cloud, in the form ODE's convex geom needs (planes, points, polygons).
#include <array>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "common/Math.h"

namespace mwb {

struct ConvexHull {
    std::vector<Vec3> points;                   ///< hull vertices only (interior points dropped)
    std::vector<std::array<double, 4>> planes;  ///< per face: unit outward normal n and d, n·x = d
    std::vector<std::vector<uint32_t>> faces;   ///< per face: indices into points, counter-clockwise seen from outside
};

struct GeometryError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Hull of `xyz` (flat, (n, 3), metres). Coplanar triangles are merged into one convex polygon and
/// vertices lying on a polygon's straight edge are dropped, as are duplicates and interior points.
/// Distances below 1e-9 of the cloud's half bounding-box diagonal count as zero. Output points are
/// copies of input points (bit-exact). Throws GeometryError when the input is not finite, not a
/// multiple of 3, or spans no volume (fewer than 4 points, all coincident, collinear or coplanar).
ConvexHull compute_convex_hull(const std::vector<double>& xyz);

/// Half the thickness a flat shape collides with: Blender accepts a BOX or a CONVEX_HULL on a
/// plane, which Bullet collides with no thickness; ODE needs a volume.
constexpr double kFlatShapeHalfThickness_m = 0.0005;

/// The points of a flat CONVEX_HULL (all in one plane, not on one line) copied
/// kFlatShapeHalfThickness_m to either side of their plane, so they span a thin slab; any other
/// point set unchanged. Flatness uses compute_convex_hull's tolerance.
std::vector<double> thicken_flat_points(const std::vector<double>& xyz);

/// Whether a triangle mesh is the whole surface of its convex hull: closed and convex (a box), or
/// flat without holes or notches (a ground plane). Every triangle lies in a hull face and the
/// triangles in each face cover it exactly once. Such a mesh can collide as its hull.
bool mesh_fills_its_hull(const std::vector<double>& vertices, const std::vector<uint32_t>& triangles);

}  // namespace mwb
