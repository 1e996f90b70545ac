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

/// Hull of `xyz` (flat, (n, 3)). Coplanar faces are merged into one polygon. Throws GeometryError
/// when the points span no volume (fewer than 4 points, or all coplanar within a relative tolerance).
ConvexHull compute_convex_hull(const std::vector<double>& xyz);

}  // namespace mwb
