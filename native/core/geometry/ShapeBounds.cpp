#include "geometry/ShapeBounds.h"

#include <algorithm>
#include <cmath>

#include "common/PortableMath.h"

namespace mwb {

double shape_bounding_radius(const Shape& shape) {
    switch (shape.type) {
        case ShapeType::Box: return norm(shape.half_extents_m);
        case ShapeType::Sphere: return shape.radius_m;
        case ShapeType::Capsule: return std::max(shape.radius_m, shape.height_m / 2);
        case ShapeType::Cylinder:
        case ShapeType::Cone: return portable::hypot(shape.radius_m, shape.height_m / 2);
        case ShapeType::ConvexHull:
        case ShapeType::Mesh: {
            double r = 0;
            for (size_t i = 0; i + 2 < shape.vertices_m.size(); i += 3)
                r = std::max(r, norm({shape.vertices_m[i], shape.vertices_m[i + 1], shape.vertices_m[i + 2]}));
            return r;
        }
        case ShapeType::Compound: {
            double r = 0;
            for (const Shape& child : shape.children)
                r = std::max(r, norm(child.offset.location) + shape_bounding_radius(child));
            return r;
        }
    }
    return 0;
}

double body_bounding_radius(const Body& body) {
    return shape_bounding_radius(body.shape) + (body.use_margin ? body.collision_margin_m : 0.0);
}

}  // namespace mwb
