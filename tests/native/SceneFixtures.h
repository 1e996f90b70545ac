#pragma once
// Small scenes with known physics, built in code for the simulation tests.
#include <string>
#include <vector>

#include "scene/Scene.h"

namespace mwb::fixtures {

inline Body ground(const std::string& name = "Ground", double half_size = 10) {
    Body b;
    b.name = name;
    b.type = BodyType::Passive;
    b.shape.type = ShapeType::Box;
    b.shape.half_extents_m = {half_size, half_size, 0.5};
    b.initial.location = {0, 0, -0.5};  // top face at z = 0
    return b;
}

inline Body sphere(const std::string& name, const Vec3& location, double radius = 0.5) {
    Body b;
    b.name = name;
    b.shape.type = ShapeType::Sphere;
    b.shape.radius_m = radius;
    b.initial.location = location;
    return b;
}

inline Body box(const std::string& name, const Vec3& location, const Vec3& half_extents = {0.2, 0.2, 0.2}) {
    Body b;
    b.name = name;
    b.shape.type = ShapeType::Box;
    b.shape.half_extents_m = half_extents;
    b.initial.location = location;
    return b;
}

inline Scene ball_on_plane(double drop_height = 2.0, double restitution = 0.0) {
    Scene s;
    s.name = "ball_on_plane";
    s.world.frame_end = 241;  // 10 s at 24 fps
    s.bodies.push_back(ground());
    s.bodies.push_back(sphere("Ball", {0, 0, drop_height}));
    s.bodies[0].restitution = 1.0;
    s.bodies[1].restitution = restitution;
    return s;
}

/// `count` boxes dropped in a loose grid onto a floor inside four walls, with small random
/// location and spin variation.
inline Scene pile(int count, double duration_frames = 73) {
    Scene s;
    s.name = "pile";
    s.world.frame_end = 1 + static_cast<int>(duration_frames);
    s.bodies.push_back(ground());
    const double wall = 1.6;
    for (int k = 0; k < 4; ++k) {
        Body w = box("Wall" + std::to_string(k), {0, 0, 1}, {k < 2 ? 0.1 : wall, k < 2 ? wall : 0.1, 1});
        w.type = BodyType::Passive;
        w.initial.location = {k == 0 ? -wall : k == 1 ? wall : 0, k == 2 ? -wall : k == 3 ? wall : 0, 1};
        s.bodies.push_back(w);
    }
    for (int i = 0; i < count; ++i) {
        Body b = box("Box" + std::to_string(i), {-0.9 + 0.6 * (i % 4), -0.9 + 0.6 * ((i / 4) % 4), 0.4 + 0.5 * (i / 16)});
        b.variation.location_min_m = {-0.05, -0.05, 0};
        b.variation.location_max_m = {0.05, 0.05, 0.2};
        b.variation.angular_velocity_min = {-2, -2, -2};
        b.variation.angular_velocity_max = {2, 2, 2};
        s.bodies.push_back(b);
    }
    return s;
}

/// A passive triangle-mesh quad (two triangles) through four corners, counter-clockwise from above.
inline Body mesh_quad(const std::string& name, const std::vector<double>& corners) {
    Body quad;
    quad.name = name;
    quad.type = BodyType::Passive;
    quad.shape.type = ShapeType::Mesh;
    quad.shape.vertices_m = corners;
    quad.shape.triangles = {0, 1, 2, 0, 2, 3};
    return quad;
}

/// A hinge between bodies `a` and `b` about the world Z axis through `pivot`.
inline Constraint hinge(const std::string& name, const std::string& a, const std::string& b, const Vec3& pivot) {
    Constraint c;
    c.name = name;
    c.type = ConstraintType::Hinge;
    c.body_a = a;
    c.body_b = b;
    c.frame.location = pivot;
    return c;
}

/// A passive triangle-mesh ramp (two triangles) tilted 20° with boxes and a jointed pair on it.
inline Scene mesh_ramp_with_joints() {
    Scene s = pile(6, 48);
    s.name = "mesh_ramp";
    s.bodies.push_back(mesh_quad("Ramp", {-1.5, -1.5, 1.0, 1.5, -1.5, 0.2, 1.5, 1.5, 0.2, -1.5, 1.5, 1.0}));
    Body a = box("LinkA", {-1.0, 0.0, 1.6});
    Body b = box("LinkB", {-0.5, 0.0, 1.6});
    a.variation.location_min_m = {-0.1, -0.1, 0};
    a.variation.location_max_m = {0.1, 0.1, 0};
    s.bodies.push_back(a);
    s.bodies.push_back(b);
    Constraint link = hinge("Link", "LinkA", "LinkB", {-0.75, 0.0, 1.6});
    link.frame.rotation = quat_from_axis_angle({1, 0, 0}, 1.5707963267948966);  // axis along -Y
    s.constraints.push_back(link);
    return s;
}

}  // namespace mwb::fixtures
