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

/// Mass properties of `shape` scaled to total mass `mass_kg`. Compound shapes sum their children
/// (placed by each child's offset); Mesh shapes are treated as their closed surface (volume from
/// signed tetrahedra) or, if not closed, as their convex hull. Throws GeometryError for shapes
/// with no volume.
MassProperties compute_mass_properties(const Shape& shape, double mass_kg);

}  // namespace mwb
