#pragma once
// Centre of mass and inertia of a shape at uniform density, in the shape's local frame.
#include <array>

#include "scene/Scene.h"

namespace mwb {

struct MassProperties {
    double volume_m3 = 0;
    Vec3 center_of_mass_m{0, 0, 0};        ///< in the shape's local frame (the object origin frame)
    std::array<double, 9> inertia{};       ///< row-major 3x3 about the centre of mass, for `mass_kg`
};

/// Mass properties of `shape` scaled to total mass `mass_kg`, in the shape's local frame:
/// - Box, Sphere, Cylinder (axis Z) and Capsule (axis Z; cylinder of length height_m - 2 radius_m
///   plus two hemispheres) are centred on the origin.
/// - Cone runs along Z with its base disc at z = -height_m/2 and apex at +height_m/2 (centred like
///   Blender's cone primitive and Bullet's cone), so its centre of mass is at z = -height_m/4.
/// - ConvexHull: the solid hull of `vertices_m`.
/// - Mesh: the solid enclosed by its triangles when they form a closed, consistently wound surface
///   (either winding); otherwise the convex hull of its vertices.
/// - Compound: children placed by their `offset`, mass split by volume (uniform density).
/// Throws GeometryError for shapes with no volume or invalid sizes (non-positive, capsule height
/// below twice its radius, mesh indices out of range).
MassProperties compute_mass_properties(const Shape& shape, double mass_kg);

}  // namespace mwb
