#pragma once
// Conservative sizes of shapes, for swept-volume queries.
#include "scene/Scene.h"

namespace mwb {

/// Radius of a sphere about the shape's frame origin (the object origin) containing the shape.
double shape_bounding_radius(const Shape& shape);
/// The same for a body, including its collision margin when the body uses one.
double body_bounding_radius(const Body& body);

}  // namespace mwb
