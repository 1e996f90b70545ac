#include "scene/SceneValidation.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

#include "geometry/ConvexHull.h"

namespace mwb {
namespace {

constexpr double kUnitQuaternionTolerance = 1e-6;
// A triangle counts as degenerate when its doubled area is below this fraction of the mesh's
// squared bounding-box diagonal.
constexpr double kDegenerateAreaTolerance = 1e-12;

// Shortest text that reads back as the same double, so messages show what the user typed.
std::string format_number(double value) {
    char text[32];
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(text, sizeof text, "%.*g", precision, value);
        if (std::strtod(text, nullptr) == value) break;
    }
    return text;
}

std::string axis_suffix(int axis) { return "[" + std::to_string(axis) + "]"; }

// Collects problems about one object ("body 'Cube'") as "<object>: <field> <text>".
class Checker {
public:
    Checker(std::vector<std::string>& problems, std::string object)
        : problems_(problems), object_(std::move(object)) {}

    void fail(const std::string& field, const std::string& text) {
        problems_.push_back(object_ + ": " + field + (field.empty() ? "" : " ") + text);
    }

    bool finite(const std::string& field, double value) {
        if (std::isfinite(value)) return true;
        fail(field, "must be a finite number, got " + format_number(value));
        return false;
    }
    template <size_t N>
    bool finite(const std::string& field, const std::array<double, N>& values) {
        bool ok = true;
        for (size_t k = 0; k < N; ++k) ok = finite(field + axis_suffix(static_cast<int>(k)), values[k]) && ok;
        return ok;
    }
    void greater(const std::string& field, double value, double bound, const std::string& context = "") {
        if (finite(field, value) && !(value > bound))
            fail(field, "must be > " + format_number(bound) + context + ", got " + format_number(value));
    }
    void at_least(const std::string& field, double value, double bound) {
        if (finite(field, value) && value < bound)
            fail(field, "must be >= " + format_number(bound) + ", got " + format_number(value));
    }
    void fraction(const std::string& field, double value) {
        if (finite(field, value) && (value < 0 || value > 1))
            fail(field, "must be between 0 and 1, got " + format_number(value));
    }
    void unit_quaternion(const std::string& field, const Quat& q) {
        if (!finite(field, q)) return;
        const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (std::fabs(length - 1) > kUnitQuaternionTolerance)
            fail(field, "must be a unit quaternion (w, x, y, z) with |q| = 1 within 1e-6 relative, got |q| = " +
                            format_number(length));
    }
    void transform(const std::string& field, const Transform& t) {
        finite(field + ".location", t.location);
        unit_quaternion(field + ".rotation", t.rotation);
    }
    void range(const std::string& min_field, double min, const std::string& max_field, double max) {
        if (finite(min_field, min) && finite(max_field, max) && min > max)
            fail(min_field, "(" + format_number(min) + ") is greater than " + max_field + " (" + format_number(max) + ")");
    }
    void ranges(const std::string& min_field, const Vec3& min, const std::string& max_field, const Vec3& max) {
        for (int k = 0; k < 3; ++k) range(min_field + axis_suffix(k), min[k], max_field + axis_suffix(k), max[k]);
    }

private:
    std::vector<std::string>& problems_;
    std::string object_;
};

std::string body_label(const Body& body, size_t index) {
    return body.name.empty() ? "body #" + std::to_string(index) + " (no name)" : "body '" + body.name + "'";
}
std::string constraint_label(const Constraint& c, size_t index) {
    return c.name.empty() ? "constraint #" + std::to_string(index) + " (no name)" : "constraint '" + c.name + "'";
}

// (n, 3) finite coordinates; reports and returns false otherwise.
bool check_points(Checker& check, const std::string& field, const std::vector<double>& xyz) {
    if (xyz.size() % 3 != 0) {
        check.fail(field, "must hold (n, 3) coordinates, got " + std::to_string(xyz.size()) + " numbers");
        return false;
    }
    for (size_t i = 0; i < xyz.size(); ++i)
        if (!check.finite(field + axis_suffix(static_cast<int>(i)), xyz[i])) return false;
    return true;
}

void check_convex_hull(Checker& check, const std::string& field, const Shape& shape) {
    const std::string vertices = field + ".vertices_m";
    if (!check_points(check, vertices, shape.vertices_m)) return;
    if (shape.vertices_m.size() < 12) {
        check.fail(vertices, "needs at least 4 points for a CONVEX_HULL, got " + std::to_string(shape.vertices_m.size() / 3));
        return;
    }
    try {
        compute_convex_hull(thicken_flat_points(shape.vertices_m));
    } catch (const GeometryError& error) {
        check.fail(vertices, std::string("span no volume: ") + error.what());
    }
}

bool mesh_has_area(const std::vector<double>& xyz, const std::vector<uint32_t>& triangles) {
    Vec3 lo{xyz[0], xyz[1], xyz[2]}, hi = lo;
    for (size_t i = 0; i < xyz.size(); ++i) lo[i % 3] = std::min(lo[i % 3], xyz[i]), hi[i % 3] = std::max(hi[i % 3], xyz[i]);
    const double diagonal = norm(sub(hi, lo));
    auto vertex = [&](uint32_t i) { return Vec3{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; };
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const Vec3 a = vertex(triangles[t]);
        const Vec3 doubled = cross(sub(vertex(triangles[t + 1]), a), sub(vertex(triangles[t + 2]), a));
        if (norm(doubled) > kDegenerateAreaTolerance * diagonal * diagonal) return true;
    }
    return false;
}

void check_mesh(Checker& check, const std::string& field, const Shape& shape) {
    if (!check_points(check, field + ".vertices_m", shape.vertices_m)) return;
    const std::vector<uint32_t>& triangles = shape.triangles;
    if (triangles.empty()) return check.fail(field + ".triangles", "is empty; a MESH needs at least one triangle");
    if (triangles.size() % 3 != 0)
        return check.fail(field + ".triangles",
                          "must hold (m, 3) vertex indices, got " + std::to_string(triangles.size()) + " numbers");
    const size_t vertex_count = shape.vertices_m.size() / 3;
    for (size_t i = 0; i < triangles.size(); ++i) {
        if (triangles[i] >= vertex_count)
            return check.fail(field + ".triangles" + axis_suffix(static_cast<int>(i)),
                              "= " + std::to_string(triangles[i]) + " is out of range (" + std::to_string(vertex_count) +
                                  " vertices)");
    }
    if (!mesh_has_area(shape.vertices_m, triangles))
        check.fail(field + ".triangles", "are all degenerate (zero area)");
}

constexpr int kMaxCompoundDepth = 32;

void check_shape(Checker& check, const std::string& field, const Shape& shape, bool simulated, int depth) {
    switch (shape.type) {
        case ShapeType::Box:
        {
            // A flat BOX (a plane) is what Blender gives a BOX shape on a plane; a line or a point is not.
            int flat_axes = 0;
            for (int k = 0; k < 3; ++k) {
                check.at_least(field + ".half_extents_m" + axis_suffix(k), shape.half_extents_m[k], 0);
                flat_axes += shape.half_extents_m[k] == 0;
            }
            if (flat_axes > 1) check.fail(field + ".half_extents_m", "has more than one side of length 0 (a flat BOX may have one)");
            break;
        }
        case ShapeType::Sphere: check.greater(field + ".radius_m", shape.radius_m, 0); break;
        case ShapeType::Capsule:
            check.greater(field + ".radius_m", shape.radius_m, 0);
            check.greater(field + ".height_m", shape.height_m, 0);
            if (shape.radius_m > 0 && shape.height_m > 0 && shape.height_m < 2 * shape.radius_m)
                check.fail(field + ".height_m", "(" + format_number(shape.height_m) +
                                                    ") must be at least 2 * radius_m for a CAPSULE (the height includes both caps)");
            break;
        case ShapeType::Cylinder:
        case ShapeType::Cone:
            check.greater(field + ".radius_m", shape.radius_m, 0);
            check.greater(field + ".height_m", shape.height_m, 0);
            break;
        case ShapeType::ConvexHull: check_convex_hull(check, field, shape); break;
        case ShapeType::Mesh:
            if (simulated)
                check.fail(field, "is a MESH on an ACTIVE body: use CONVEX_HULL for active bodies; triangle meshes "
                                  "collide only as passive/animated bodies");
            check_mesh(check, field, shape);
            break;
        case ShapeType::Compound:
            if (shape.children.empty()) return check.fail(field + ".children", "is empty; a COMPOUND needs at least one child");
            if (depth >= kMaxCompoundDepth)
                return check.fail(field, "nests compounds deeper than " + std::to_string(kMaxCompoundDepth) + " levels");
            for (size_t i = 0; i < shape.children.size(); ++i) {
                const std::string child = field + ".children" + axis_suffix(static_cast<int>(i));
                check.transform(child + ".offset", shape.children[i].offset);
                check_shape(check, child, shape.children[i], simulated, depth + 1);
            }
            break;
    }
}

void check_animation(Checker& check, const Body& body) {
    const KinematicTrack& track = body.animation;
    for (size_t i = 0; i < track.times_s.size(); ++i) check.finite("animation.times_s" + axis_suffix(static_cast<int>(i)), track.times_s[i]);
    for (size_t i = 0; i < track.transforms.size(); ++i)
        check.transform("animation.transforms" + axis_suffix(static_cast<int>(i)), track.transforms[i]);
    if (body.animated_until_s != 0) {
        check.greater("animated_until_s", body.animated_until_s, 0);
        if (body.kinematic || body.type != BodyType::Active)
            check.fail("animated_until_s", "is for an ACTIVE body whose \"Animated\" is keyed off; this one is " +
                                               std::string(body.kinematic ? "animated throughout" : "PASSIVE"));
        if (track.times_s.empty()) check.fail("animated_until_s", "needs the animation the body follows until then");
    }
    if (!body.kinematic && body.animated_until_s <= 0) return;
    if (track.times_s.size() != track.transforms.size())
        check.fail("animation", "has " + std::to_string(track.times_s.size()) + " times_s but " +
                                    std::to_string(track.transforms.size()) + " transforms; they must match");
    for (size_t i = 1; i < track.times_s.size(); ++i) {
        if (!(track.times_s[i] > track.times_s[i - 1])) {
            check.fail("animation.times_s" + axis_suffix(static_cast<int>(i)),
                       "must be greater than the previous time (" + format_number(track.times_s[i - 1]) + "), got " +
                           format_number(track.times_s[i]));
            return;
        }
    }
}

void check_variation(Checker& check, const VariationRanges& v) {
    const std::string p = "variation.";
    check.ranges(p + "location_min_m", v.location_min_m, p + "location_max_m", v.location_max_m);
    check.ranges(p + "rotation_min_rad", v.rotation_min_rad, p + "rotation_max_rad", v.rotation_max_rad);
    check.ranges(p + "linear_velocity_min", v.linear_velocity_min, p + "linear_velocity_max", v.linear_velocity_max);
    check.ranges(p + "angular_velocity_min", v.angular_velocity_min, p + "angular_velocity_max", v.angular_velocity_max);
    check.range(p + "mass_scale_min", v.mass_scale_min, p + "mass_scale_max", v.mass_scale_max);
    check.range(p + "friction_scale_min", v.friction_scale_min, p + "friction_scale_max", v.friction_scale_max);
    check.range(p + "restitution_scale_min", v.restitution_scale_min, p + "restitution_scale_max", v.restitution_scale_max);
    check.greater(p + "mass_scale_min", v.mass_scale_min, 0);
    check.at_least(p + "friction_scale_min", v.friction_scale_min, 0);
    check.at_least(p + "restitution_scale_min", v.restitution_scale_min, 0);
}

void check_body(Checker& check, const Body& body) {
    const bool active = body.type == BodyType::Active;
    check.transform("initial", body.initial);
    check.finite("initial_linear_velocity", body.initial_linear_velocity);
    check.finite("initial_angular_velocity", body.initial_angular_velocity);
    if (active) {
        check.greater("mass_kg", body.mass_kg, 0, " for an ACTIVE body");
    } else {
        check.finite("mass_kg", body.mass_kg);
    }
    check.at_least("friction", body.friction, 0);
    check.at_least("restitution", body.restitution, 0);
    check.at_least("collision_margin_m", body.collision_margin_m, 0);
    check.fraction("linear_damping", body.linear_damping);
    check.fraction("angular_damping", body.angular_damping);
    check.at_least("deactivation.linear_speed", body.deactivation.linear_speed, 0);
    check.at_least("deactivation.angular_speed", body.deactivation.angular_speed, 0);
    if (body.has_center_of_mass) check.finite("center_of_mass_local_m", body.center_of_mass_local_m);
    check_shape(check, "shape", body.shape, active && !body.kinematic, 0);
    check_animation(check, body);
    check_variation(check, body.variation);
}

void check_bodies(const Scene& scene, std::vector<std::string>& problems) {
    std::map<std::string, size_t> first_use;
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
        const Body& body = scene.bodies[i];
        Checker check(problems, body_label(body, i));
        if (body.name.empty()) check.fail("name", "must not be empty");
        auto [it, inserted] = first_use.emplace(body.name, i);
        if (!inserted && !body.name.empty())
            check.fail("name", "is used by bodies[" + std::to_string(it->second) + "] and bodies[" + std::to_string(i) +
                                   "]; body names must be unique");
        check_body(check, body);
    }
}

void check_limits(Checker& check, const std::string& field, const AxisLimits& limits) {
    for (int k = 0; k < 3; ++k) {
        const std::string axis = axis_suffix(k);
        const bool lower_finite = check.finite(field + ".lower" + axis, limits.lower[k]);
        const bool upper_finite = check.finite(field + ".upper" + axis, limits.upper[k]);
        if (lower_finite && upper_finite && limits.enabled[k] && limits.lower[k] > limits.upper[k])
            check.fail(field + ".lower" + axis, "(" + format_number(limits.lower[k]) + ") is greater than " + field +
                                                    ".upper" + axis + " (" + format_number(limits.upper[k]) + ")");
    }
}

void check_springs(Checker& check, const std::string& field, const AxisSprings& springs) {
    for (int k = 0; k < 3; ++k) {
        check.at_least(field + ".stiffness" + axis_suffix(k), springs.stiffness[k], 0);
        check.at_least(field + ".damping" + axis_suffix(k), springs.damping[k], 0);
    }
}

bool linear_axes_locked(const AxisLimits& limits) {
    for (int k = 0; k < 3; ++k)
        if (!limits.enabled[k] || limits.lower[k] != 0 || limits.upper[k] != 0) return false;
    return true;
}

void check_constraint_bodies(Checker& check, const Scene& scene, const Constraint& c) {
    if (c.body_a.empty() && c.body_b.empty())
        return check.fail("body_a/body_b", "are both empty; a constraint needs at least one body");
    if (!c.body_a.empty() && scene.body_index(c.body_a) < 0) check.fail("body_a", "'" + c.body_a + "' is not a body in the scene");
    if (!c.body_b.empty() && scene.body_index(c.body_b) < 0) check.fail("body_b", "'" + c.body_b + "' is not a body in the scene");
    if (c.body_a == c.body_b) check.fail("body_a/body_b", "are both '" + c.body_a + "'; a body cannot be constrained to itself");
}

void check_constraint(Checker& check, const Scene& scene, const Constraint& c) {
    check_constraint_bodies(check, scene, c);
    check.transform("frame", c.frame);
    check.at_least("breaking_threshold", c.breaking_threshold, 0);
    check_limits(check, "linear_limits", c.linear_limits);
    check_limits(check, "angular_limits", c.angular_limits);
    check_springs(check, "linear_springs", c.linear_springs);
    check_springs(check, "angular_springs", c.angular_springs);
    check.finite("motor_linear_target_velocity", c.motor_linear_target_velocity);
    check.finite("motor_angular_target_velocity", c.motor_angular_target_velocity);
    check.at_least("motor_linear_max_impulse", c.motor_linear_max_impulse, 0);
    check.at_least("motor_angular_max_impulse", c.motor_angular_max_impulse, 0);
    const bool generic = c.type == ConstraintType::Generic || c.type == ConstraintType::GenericSpring;
    // ODE has no 6-DOF joint; a GENERIC with locked linear axes maps onto a ball joint with an
    // angular motor, and anything else would silently behave differently from Blender.
    if (generic && !linear_axes_locked(c.linear_limits))
        check.fail("", std::string(to_string(c.type)) +
                           " with free or limited linear axes is not supported by the ODE engine; lock all linear axes "
                           "(linear_limits enabled with lower = upper = 0: a ball joint with angular limits) or use "
                           "SLIDER/PISTON");
}

void check_constraints(const Scene& scene, std::vector<std::string>& problems) {
    std::map<std::string, size_t> first_use;
    for (size_t i = 0; i < scene.constraints.size(); ++i) {
        const Constraint& c = scene.constraints[i];
        Checker check(problems, constraint_label(c, i));
        if (c.name.empty()) check.fail("name", "must not be empty");
        auto [it, inserted] = first_use.emplace(c.name, i);
        if (!inserted && !c.name.empty())
            check.fail("name", "is used by constraints[" + std::to_string(it->second) + "] and constraints[" +
                                   std::to_string(i) + "]; constraint names must be unique");
        check_constraint(check, scene, c);
    }
}

void check_world(const WorldSettings& world, std::vector<std::string>& problems) {
    Checker check(problems, "world");
    check.finite("gravity", world.gravity);
    check.greater("time_scale", world.time_scale, 0);
    check.greater("fps", world.fps, 0);
    if (world.substeps_per_frame < 1) check.fail("substeps_per_frame", "must be >= 1, got " + std::to_string(world.substeps_per_frame));
    if (world.solver_iterations < 1) check.fail("solver_iterations", "must be >= 1, got " + std::to_string(world.solver_iterations));
    if (world.frame_end < world.frame_start)
        check.fail("frame_end", "(" + std::to_string(world.frame_end) + ") must not be before frame_start (" +
                                    std::to_string(world.frame_start) + ")");
}

}  // namespace

std::vector<std::string> validate_scene(const Scene& scene) {
    std::vector<std::string> problems;
    check_world(scene.world, problems);
    check_bodies(scene, problems);
    check_constraints(scene, problems);
    return problems;
}

}  // namespace mwb
