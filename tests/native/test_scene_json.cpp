#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <tuple>

#include "scene/SceneJson.h"

namespace mwb {
namespace {

Shape sized(ShapeType type, double radius, double height) {
    Shape s;
    s.type = type;
    s.radius_m = radius;
    s.height_m = height;
    return s;
}

std::vector<double> cube_points(double half) {
    std::vector<double> xyz;
    for (int i = 0; i < 8; ++i) xyz.insert(xyz.end(), {i & 1 ? half : -half, i & 2 ? half : -1.0 / 3.0, i & 4 ? half : -half});
    return xyz;
}

Shape every_shape(ShapeType type) {
    switch (type) {
        case ShapeType::Box: {
            Shape s;
            s.half_extents_m = {0.1, 1.0 / 3.0, 5e-3};
            return s;
        }
        case ShapeType::Sphere: return sized(type, 0.30000000000000004, 1.0);
        case ShapeType::Capsule: return sized(type, 0.25, 1.7);
        case ShapeType::Cylinder:
        case ShapeType::Cone: return sized(type, 0.2, 0.9);
        case ShapeType::ConvexHull: {
            Shape s;
            s.type = type;
            s.vertices_m = cube_points(0.7);
            return s;
        }
        case ShapeType::Mesh: {
            Shape s;
            s.type = type;
            s.vertices_m = cube_points(2.5);
            s.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                           2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
            return s;
        }
        case ShapeType::Compound: {
            Shape s;
            s.type = type;
            Shape box = every_shape(ShapeType::Box), ball = every_shape(ShapeType::Sphere);
            box.offset.location = {0.1, -0.2, 1e-300};
            box.offset.rotation = quat_normalized({0.9, 0.1, -0.3, 0.2});
            Shape nested;
            nested.type = ShapeType::Compound;
            nested.children = {every_shape(ShapeType::Cone)};
            nested.offset.location = {-0.0, 0, 2};
            s.children = {box, ball, nested};
            return s;
        }
    }
    return {};
}

// Every shape and constraint type, every field away from its default, awkward doubles.
Scene full_scene() {
    Scene scene;
    scene.name = "Everything ü";
    scene.world = {{0.5, -0.25, -9.80665}, 0.75, 7, 23, -10, 480, 29.97002997002997};
    const ShapeType shapes[] = {ShapeType::Box,  ShapeType::Sphere,     ShapeType::Capsule, ShapeType::Cylinder,
                                ShapeType::Cone, ShapeType::ConvexHull, ShapeType::Mesh,    ShapeType::Compound};
    for (ShapeType type : shapes) {
        Body b;
        b.name = std::string("Body ") + to_string(type);
        b.type = type == ShapeType::Mesh ? BodyType::Passive : BodyType::Active;
        b.kinematic = type == ShapeType::Cone;
        b.enabled = type != ShapeType::Sphere;
        if (type == ShapeType::Capsule) b.object = "Capsule object";
        b.shape = every_shape(type);
        b.mass_kg = 0.1 + static_cast<double>(scene.bodies.size());
        b.friction = 1.0 / 7.0;
        b.restitution = 0.9;
        b.use_margin = true;
        b.collision_margin_m = 5e-324;
        b.linear_damping = 0.0;
        b.angular_damping = 1.0;
        b.collision_collections = 0xfffff;
        b.initial = {{1e10, -1e-10, 0.1}, quat_normalized({0.5, 0.5, -0.5, 0.25})};
        b.initial_linear_velocity = {1, 2, 3};
        b.initial_angular_velocity = {-4, 5.5, -6.25};
        b.has_center_of_mass = type == ShapeType::Box;
        b.center_of_mass_local_m = b.has_center_of_mass ? Vec3{0.01, 0.02, 0.03} : Vec3{0, 0, 0};
        if (b.kinematic) {
            b.animation.times_s = {0, 1.0 / 24, 2.0 / 24};
            b.animation.transforms = {Transform{}, {{0, 0, 0.1}, {1, 0, 0, 0}}, {{0, 0, 0.2}, quat_normalized({1, 1, 0, 0})}};
        }
        VariationRanges& v = b.variation;
        v.location_min_m = {-0.1, -0.2, -0.3};
        v.location_max_m = {0.1, 0.2, 0.3};
        v.rotation_min_rad = {-3.14159, 0, -1};
        v.rotation_max_rad = {3.14159, 0, 1};
        v.linear_velocity_min = {-1, -2, -3};
        v.linear_velocity_max = {1, 2, 3};
        v.angular_velocity_min = {-0.5, -0.25, -0.125};
        v.angular_velocity_max = {0.5, 0.25, 0.125};
        v.mass_scale_min = 0.5, v.mass_scale_max = 2;
        v.friction_scale_min = 0.25, v.friction_scale_max = 1.5;
        v.restitution_scale_min = 0, v.restitution_scale_max = 1.1;
        scene.bodies.push_back(b);
    }
    const ConstraintType joints[] = {ConstraintType::Fixed,   ConstraintType::Point,         ConstraintType::Hinge,
                                     ConstraintType::Slider,  ConstraintType::Piston,        ConstraintType::Generic,
                                     ConstraintType::GenericSpring, ConstraintType::Motor};
    for (ConstraintType type : joints) {
        Constraint c;
        c.name = std::string("Joint ") + to_string(type);
        c.type = type;
        c.body_a = scene.bodies[scene.constraints.size()].name;
        c.body_b = type == ConstraintType::Motor ? "" : scene.bodies[scene.constraints.size() + 1].name;
        c.enabled = type != ConstraintType::Fixed;
        c.disable_collisions = false;
        c.frame = {{0.5, 0.25, 0.125}, quat_normalized({0.1, 0.2, 0.3, 0.4})};
        c.breakable = true;
        c.breaking_threshold = 123.456;
        c.linear_limits = {{true, true, true}, {0, 0, 0}, {0, 0, 0}};
        c.angular_limits = {{true, false, true}, {-0.7, -0.1, -2}, {0.7, 0.1, 2}};
        c.linear_springs = {{true, false, false}, {100, 200, 300}, {0.1, 0.2, 0.3}};
        c.angular_springs = {{false, true, false}, {1, 2, 3}, {0.4, 0.5, 0.6}};
        c.motor_linear_enabled = true;
        c.motor_angular_enabled = true;
        c.motor_linear_target_velocity = -2.5;
        c.motor_linear_max_impulse = 3.5;
        c.motor_angular_target_velocity = 6.283185307179586;
        c.motor_angular_max_impulse = 0.001;
        scene.constraints.push_back(c);
    }
    return scene;
}

// Doubles must come back bit for bit (0.0 and -0.0 differ).
void expect_bits(double a, double b, const std::string& what) {
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << what << ": " << a << " vs " << b;
}
template <size_t N>
void expect_bits(const std::array<double, N>& a, const std::array<double, N>& b, const std::string& what) {
    for (size_t k = 0; k < N; ++k) expect_bits(a[k], b[k], what + "[" + std::to_string(k) + "]");
}
void expect_bits(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    for (size_t k = 0; k < a.size(); ++k) expect_bits(a[k], b[k], what + "[" + std::to_string(k) + "]");
}
void expect_same(const Transform& a, const Transform& b, const std::string& what) {
    expect_bits(a.location, b.location, what + ".location");
    expect_bits(a.rotation, b.rotation, what + ".rotation");
}

void expect_same(const Shape& a, const Shape& b, const std::string& what) {
    EXPECT_EQ(a.type, b.type) << what;
    expect_bits(a.half_extents_m, b.half_extents_m, what + ".half_extents_m");
    expect_bits(a.radius_m, b.radius_m, what + ".radius_m");
    expect_bits(a.height_m, b.height_m, what + ".height_m");
    expect_bits(a.vertices_m, b.vertices_m, what + ".vertices_m");
    EXPECT_EQ(a.triangles, b.triangles) << what;
    expect_same(a.offset, b.offset, what + ".offset");
    ASSERT_EQ(a.children.size(), b.children.size()) << what;
    for (size_t i = 0; i < a.children.size(); ++i) expect_same(a.children[i], b.children[i], what + ".children");
}

void expect_same(const Body& a, const Body& b) {
    const std::string w = "body " + a.name;
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.object, b.object) << a.name;
    EXPECT_EQ(a.type, b.type) << w;
    EXPECT_EQ(a.kinematic, b.kinematic) << w;
    EXPECT_EQ(a.enabled, b.enabled) << w;
    expect_same(a.shape, b.shape, w + ".shape");
    expect_bits(a.mass_kg, b.mass_kg, w + ".mass_kg");
    expect_bits(a.friction, b.friction, w + ".friction");
    expect_bits(a.restitution, b.restitution, w + ".restitution");
    EXPECT_EQ(a.use_margin, b.use_margin) << w;
    expect_bits(a.collision_margin_m, b.collision_margin_m, w + ".collision_margin_m");
    expect_bits(a.linear_damping, b.linear_damping, w + ".linear_damping");
    expect_bits(a.angular_damping, b.angular_damping, w + ".angular_damping");
    EXPECT_EQ(a.collision_collections, b.collision_collections) << w;
    expect_same(a.initial, b.initial, w + ".initial");
    expect_bits(a.initial_linear_velocity, b.initial_linear_velocity, w + ".initial_linear_velocity");
    expect_bits(a.initial_angular_velocity, b.initial_angular_velocity, w + ".initial_angular_velocity");
    EXPECT_EQ(a.has_center_of_mass, b.has_center_of_mass) << w;
    expect_bits(a.center_of_mass_local_m, b.center_of_mass_local_m, w + ".center_of_mass_local_m");
    expect_bits(a.animation.times_s, b.animation.times_s, w + ".animation.times_s");
    ASSERT_EQ(a.animation.transforms.size(), b.animation.transforms.size()) << w;
    for (size_t i = 0; i < a.animation.transforms.size(); ++i)
        expect_same(a.animation.transforms[i], b.animation.transforms[i], w + ".animation");
    const VariationRanges &va = a.variation, &vb = b.variation;
    expect_bits(va.location_min_m, vb.location_min_m, w + ".location_min_m");
    expect_bits(va.location_max_m, vb.location_max_m, w + ".location_max_m");
    expect_bits(va.rotation_min_rad, vb.rotation_min_rad, w + ".rotation_min_rad");
    expect_bits(va.rotation_max_rad, vb.rotation_max_rad, w + ".rotation_max_rad");
    expect_bits(va.linear_velocity_min, vb.linear_velocity_min, w + ".linear_velocity_min");
    expect_bits(va.linear_velocity_max, vb.linear_velocity_max, w + ".linear_velocity_max");
    expect_bits(va.angular_velocity_min, vb.angular_velocity_min, w + ".angular_velocity_min");
    expect_bits(va.angular_velocity_max, vb.angular_velocity_max, w + ".angular_velocity_max");
    expect_bits(va.mass_scale_min, vb.mass_scale_min, w + ".mass_scale_min");
    expect_bits(va.mass_scale_max, vb.mass_scale_max, w + ".mass_scale_max");
    expect_bits(va.friction_scale_min, vb.friction_scale_min, w + ".friction_scale_min");
    expect_bits(va.friction_scale_max, vb.friction_scale_max, w + ".friction_scale_max");
    expect_bits(va.restitution_scale_min, vb.restitution_scale_min, w + ".restitution_scale_min");
    expect_bits(va.restitution_scale_max, vb.restitution_scale_max, w + ".restitution_scale_max");
}

void expect_same(const Constraint& a, const Constraint& b) {
    const std::string w = "constraint " + a.name;
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.type, b.type) << w;
    EXPECT_EQ(a.body_a, b.body_a) << w;
    EXPECT_EQ(a.body_b, b.body_b) << w;
    EXPECT_EQ(a.enabled, b.enabled) << w;
    EXPECT_EQ(a.disable_collisions, b.disable_collisions) << w;
    expect_same(a.frame, b.frame, w + ".frame");
    EXPECT_EQ(a.breakable, b.breakable) << w;
    expect_bits(a.breaking_threshold, b.breaking_threshold, w + ".breaking_threshold");
    for (const auto& [la, lb, name] : {std::tuple{&a.linear_limits, &b.linear_limits, "linear_limits"},
                                       std::tuple{&a.angular_limits, &b.angular_limits, "angular_limits"}}) {
        EXPECT_EQ(la->enabled, lb->enabled) << w << name;
        expect_bits(la->lower, lb->lower, w + name + ".lower");
        expect_bits(la->upper, lb->upper, w + name + ".upper");
    }
    for (const auto& [sa, sb, name] : {std::tuple{&a.linear_springs, &b.linear_springs, "linear_springs"},
                                       std::tuple{&a.angular_springs, &b.angular_springs, "angular_springs"}}) {
        EXPECT_EQ(sa->enabled, sb->enabled) << w << name;
        expect_bits(sa->stiffness, sb->stiffness, w + name + ".stiffness");
        expect_bits(sa->damping, sb->damping, w + name + ".damping");
    }
    EXPECT_EQ(a.motor_linear_enabled, b.motor_linear_enabled) << w;
    EXPECT_EQ(a.motor_angular_enabled, b.motor_angular_enabled) << w;
    expect_bits(a.motor_linear_target_velocity, b.motor_linear_target_velocity, w + ".motor_linear_target_velocity");
    expect_bits(a.motor_linear_max_impulse, b.motor_linear_max_impulse, w + ".motor_linear_max_impulse");
    expect_bits(a.motor_angular_target_velocity, b.motor_angular_target_velocity, w + ".motor_angular_target_velocity");
    expect_bits(a.motor_angular_max_impulse, b.motor_angular_max_impulse, w + ".motor_angular_max_impulse");
}

void expect_same(const Scene& a, const Scene& b) {
    EXPECT_EQ(a.name, b.name);
    expect_bits(a.world.gravity, b.world.gravity, "world.gravity");
    expect_bits(a.world.time_scale, b.world.time_scale, "world.time_scale");
    EXPECT_EQ(a.world.substeps_per_frame, b.world.substeps_per_frame);
    EXPECT_EQ(a.world.solver_iterations, b.world.solver_iterations);
    EXPECT_EQ(a.world.frame_start, b.world.frame_start);
    EXPECT_EQ(a.world.frame_end, b.world.frame_end);
    expect_bits(a.world.fps, b.world.fps, "world.fps");
    ASSERT_EQ(a.bodies.size(), b.bodies.size());
    for (size_t i = 0; i < a.bodies.size(); ++i) expect_same(a.bodies[i], b.bodies[i]);
    ASSERT_EQ(a.constraints.size(), b.constraints.size());
    for (size_t i = 0; i < a.constraints.size(); ++i) expect_same(a.constraints[i], b.constraints[i]);
}

// The SceneError message of parsing `text`, or "" when it parses.
std::string error_of(const std::string& text) {
    try {
        scene_from_json(text);
    } catch (const SceneError& error) {
        return error.what();
    }
    return "";
}

// A valid single-body scene with `body_fields` spliced into the body object.
std::string one_body(const std::string& body_fields, const std::string& extra_top = "") {
    return R"({"format": "mwb-scene", "version": 1)" + extra_top +
           R"(, "bodies": [{"name": "Cube", "type": "ACTIVE", "shape": {"type": "BOX"})" +
           (body_fields.empty() ? "" : ", " + body_fields) + "}]}";
}

TEST(SceneJson, RoundTripKeepsEveryValueExactly) {
    const Scene original = full_scene();
    const std::string text = scene_to_json(original);
    const Scene parsed = scene_from_json(text);
    expect_same(original, parsed);
    EXPECT_EQ(scene_to_json(parsed), text);
}

TEST(SceneJson, WritesFormatVersionAndBlenderIdentifiers) {
    const std::string text = scene_to_json(full_scene());
    EXPECT_EQ(text.rfind(R"({"format":"mwb-scene","version":1,)", 0), 0u) << text.substr(0, 80);
    for (const char* id : {"\"ACTIVE\"", "\"PASSIVE\"", "\"CONVEX_HULL\"", "\"GENERIC_SPRING\"", "\"collision_collections\":1048575"})
        EXPECT_NE(text.find(id), std::string::npos) << id;
}

TEST(SceneJson, MissingOptionalFieldsTakeSceneDefaults) {
    const Scene scene = scene_from_json(one_body(""));
    const Body& b = scene.bodies.at(0);
    const Body defaults;
    EXPECT_EQ(b.mass_kg, defaults.mass_kg);
    EXPECT_EQ(b.linear_damping, defaults.linear_damping);
    EXPECT_EQ(b.collision_collections, defaults.collision_collections);
    EXPECT_EQ(b.shape.half_extents_m, defaults.shape.half_extents_m);
    EXPECT_FALSE(b.has_center_of_mass);
    EXPECT_EQ(scene.world.fps, WorldSettings{}.fps);
    EXPECT_EQ(scene.world.gravity, WorldSettings{}.gravity);
    // Integral floats are accepted where integers are expected.
    EXPECT_EQ(scene_from_json(one_body("", R"(, "world": {"frame_end": 48.0})")).world.frame_end, 48);
}

TEST(SceneJson, WrongTypesNameTheObjectAndField) {
    const std::string cases[][2] = {
        {R"("mass_kg": "heavy")", "body 'Cube' (bodies[0]).mass_kg: expected a number, got string"},
        {R"("mass_kg": null)", "body 'Cube' (bodies[0]).mass_kg: expected a number, got null"},
        {R"("friction": [1])", "body 'Cube' (bodies[0]).friction: expected a number, got array"},
        {R"("use_margin": 1)", "body 'Cube' (bodies[0]).use_margin: expected true or false, got number"},
        {R"("collision_collections": -1)", "body 'Cube' (bodies[0]).collision_collections: expected an integer in [0, 4294967295], got -1"},
        {R"("collision_collections": 1.5)", "collision_collections: expected an integer"},
        {R"("initial": {"location": [1, 2]})", "body 'Cube' (bodies[0]).initial.location: expected an array of 3 numbers, got 2 elements"},
        {R"("initial": {"rotation": [1, 0, 0, null]})", "body 'Cube' (bodies[0]).initial.rotation[3]: expected a number, got null"},
        {R"("initial": [0, 0, 0])", "body 'Cube' (bodies[0]).initial: expected an object, got array"},
        {R"("initial_linear_velocity": "fast")", "initial_linear_velocity: expected an array of 3 numbers, got string"},
        {R"("center_of_mass_local_m": [0, 0, 0, 0])", "center_of_mass_local_m: expected an array of 3 numbers, got 4 elements"},
        {R"("animation": {"times_s": [0, "1"]})", "body 'Cube' (bodies[0]).animation.times_s[1]: expected a number, got string"},
        {R"("animation": {"transforms": [{"location": [0, 0, 0], "spin": 1}]})",
         "body 'Cube' (bodies[0]).animation.transforms[0]: unknown field 'spin'"},
        {R"("variation": {"mass_scale_min": true})", "body 'Cube' (bodies[0]).variation.mass_scale_min: expected a number, got boolean"},
        {R"("variation": {"location_min": [0, 0, 0]})", "body 'Cube' (bodies[0]).variation: unknown field 'location_min'"},
        {R"("mas_kg": 2)", "body 'Cube' (bodies[0]): unknown field 'mas_kg'"},
        {R"("kinematic": "yes")", "body 'Cube' (bodies[0]).kinematic: expected true or false, got string"},
    };
    for (const auto& [fields, expected] : cases) {
        const std::string message = error_of(one_body(fields));
        EXPECT_NE(message.find(expected), std::string::npos) << fields << "\n  got: " << message;
    }
}

TEST(SceneJson, ShapeAndEnumErrors) {
    const std::string head = R"({"format": "mwb-scene", "version": 1, "bodies": [)";
    const std::string cases[][2] = {
        {R"({"name": "A", "type": "ACTIV", "shape": {"type": "BOX"}})",
         "body 'A' (bodies[0]).type: unknown body type 'ACTIV' (expected one of ACTIVE, PASSIVE)"},
        {R"({"name": "A", "type": "ACTIVE", "shape": {"type": "SPHERES"}})",
         "body 'A' (bodies[0]).shape.type: unknown shape type 'SPHERES' (expected one of BOX, SPHERE, CAPSULE"},
        {R"({"name": "A", "type": "ACTIVE", "shape": {"type": "BOX", "radius_m": 1}})",
         "body 'A' (bodies[0]).shape: unknown field 'radius_m' for a BOX shape"},
        {R"({"name": "A", "type": "ACTIVE", "shape": {"radius_m": 1}})", "body 'A' (bodies[0]).shape.type: missing required field"},
        {R"({"name": "A", "type": "ACTIVE"})", "body 'A' (bodies[0]).shape: missing required field"},
        {R"({"type": "ACTIVE", "shape": {"type": "BOX"}})", "bodies[0].name: missing required field"},
        {R"({"name": 7, "type": "ACTIVE", "shape": {"type": "BOX"}})", "bodies[0].name: expected a string, got number"},
        {R"({"name": "A", "shape": {"type": "BOX"}})", "body 'A' (bodies[0]).type: missing required field"},
        {R"({"name": "A", "type": "PASSIVE", "shape": {"type": "MESH", "triangles": [0, 1, -2]}})",
         "body 'A' (bodies[0]).shape.triangles[2]: expected an integer in [0, 4294967295], got -2"},
        {R"({"name": "A", "type": "ACTIVE", "shape": {"type": "CONVEX_HULL", "vertices_m": [0, 0, null]}})",
         "body 'A' (bodies[0]).shape.vertices_m[2]: expected a number, got null"},
        {R"({"name": "A", "type": "ACTIVE", "shape": {"type": "COMPOUND", "children": [{"type": "BOX", "offset": {"rotation": [1, 0]}}]}})",
         "body 'A' (bodies[0]).shape.children[0].offset.rotation: expected an array of 4 numbers, got 2 elements"},
        {R"({"name": "A", "type": "ACTIVE", "shape": {"type": "COMPOUND", "children": {}}})",
         "body 'A' (bodies[0]).shape.children: expected an array of shapes, got object"},
        {R"(42)", "bodies[0]: expected an object, got number"},
    };
    for (const auto& [body, expected] : cases) {
        const std::string message = error_of(head + body + "]}");
        EXPECT_NE(message.find(expected), std::string::npos) << body << "\n  got: " << message;
    }
}

TEST(SceneJson, ConstraintWorldAndTopLevelErrors) {
    const std::string cases[][2] = {
        {R"(, "constraints": [{"name": "J", "type": "WELD", "body_a": "Cube"}])",
         "constraint 'J' (constraints[0]).type: unknown constraint type 'WELD' (expected one of FIXED, POINT"},
        {R"(, "constraints": [{"name": "J", "type": "HINGE", "body_a": "Cube", "angular_limits": {"enabled": [true, 1, false]}}])",
         "constraint 'J' (constraints[0]).angular_limits.enabled[1]: expected true or false, got number"},
        {R"(, "constraints": [{"name": "J", "type": "HINGE", "body_a": "Nobody"}])",
         "constraint 'J': body_a 'Nobody' is not a body in the scene"},
        {R"(, "constraints": {})", "constraints: expected an array, got object"},
        {R"(, "world": {"fps": "24"})", "world.fps: expected a number, got string"},
        {R"(, "world": {"substeps_per_frame": 1e10})", "world.substeps_per_frame: expected an integer in [-2147483648, 2147483647]"},
        {R"(, "world": {"gravity": [0, 0]})", "world.gravity: expected an array of 3 numbers, got 2 elements"},
        {R"(, "world": {"frame_end": -5})", "world: frame_end (-5) must not be before frame_start (1)"},
        {R"(, "name": ["x"])", "name: expected a string, got array"},
        {R"(, "extra": 1)", "top level: unknown field 'extra'"},
    };
    for (const auto& [extra, expected] : cases) {
        const std::string message = error_of(one_body("", extra));
        EXPECT_NE(message.find(expected), std::string::npos) << extra << "\n  got: " << message;
    }
}

TEST(SceneJson, CollectsParseAndValidationProblemsTogether) {
    const std::string message = error_of(one_body(R"("mass_kg": -1, "friction": "x", "restitution": -2)"));
    EXPECT_NE(message.find("body 'Cube' (bodies[0]).friction: expected a number, got string"), std::string::npos) << message;
    EXPECT_NE(message.find("body 'Cube': mass_kg must be > 0 for an ACTIVE body, got -1"), std::string::npos) << message;
    EXPECT_NE(message.find("body 'Cube': restitution must be >= 0, got -2"), std::string::npos) << message;
    EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 2) << message;
}

TEST(SceneJson, FormatAndVersionAreChecked) {
    EXPECT_NE(error_of(R"({"format": "gltf", "version": 1})").find("format: expected \"mwb-scene\", got \"gltf\""),
              std::string::npos);
    EXPECT_NE(error_of(R"({"version": 1})").find("not a Many-Worlds Browser scene"), std::string::npos);
    EXPECT_NE(error_of(R"({"format": "mwb-scene"})").find("version: missing required field"), std::string::npos);
    EXPECT_NE(error_of(R"({"format": "mwb-scene", "version": 2})").find("format version 2, newer than the 1"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"format": "mwb-scene", "version": 0})").find("version: expected 1 or later"), std::string::npos);
    EXPECT_NE(error_of(R"({"format": "mwb-scene", "version": "1"})").find("version: expected an integer"), std::string::npos);
    EXPECT_NE(error_of("[1, 2]").find("expected an object at the top level, got array"), std::string::npos);
    EXPECT_EQ(error_of(R"({"format": "mwb-scene", "version": 1})"), "");
}

TEST(SceneJson, MalformedJsonGivesTheParserPosition) {
    for (const std::string text : {"", "{", R"({"format": "mwb-scene",)", "{\"a\": tru}", "{\"a\": \"\xff\"}", "nul", "{} {}"}) {
        const std::string message = error_of(text);
        EXPECT_EQ(message.rfind("scene JSON is malformed: ", 0), 0u) << message;
        EXPECT_NE(message.find("line 1, column"), std::string::npos) << message;
    }
}

TEST(SceneJson, NumbersBeyondDoubleRangeAreRefused) {
    EXPECT_EQ(error_of(one_body(R"("mass_kg": 1e999)")), "scene JSON is malformed: number overflow parsing '1e999'");
}

TEST(SceneJson, DeeplyNestedCompoundsAreRefused) {
    std::string shape = R"({"type": "BOX"})";
    for (int i = 0; i < 2000; ++i) shape = R"({"type": "COMPOUND", "children": [)" + shape + "]}";
    const std::string message = error_of(R"({"format": "mwb-scene", "version": 1, "bodies": [{"name": "A", "type": "ACTIVE", "shape": )" + shape + "}]}");
    EXPECT_NE(message.find("compounds nest deeper than 32 levels"), std::string::npos) << message.substr(0, 300);
}

TEST(SceneJson, LoadSceneFileNamesThePath) {
    const std::string path = ::testing::TempDir() + "mwb_scene_json_test.json";
    {
        std::ofstream out(path);
        out << scene_to_json(full_scene());
    }
    expect_same(load_scene_file(path), full_scene());
    {
        std::ofstream out(path);
        out << one_body(R"("mass_kg": "x")");
    }
    try {
        load_scene_file(path);
        ADD_FAILURE() << "expected a SceneError";
    } catch (const SceneError& error) {
        EXPECT_NE(std::string(error.what()).find("scene file '" + path + "'"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("mass_kg: expected a number"), std::string::npos) << error.what();
    }
    std::remove(path.c_str());
    try {
        load_scene_file(path);
        ADD_FAILURE() << "expected a SceneError";
    } catch (const SceneError& error) {
        EXPECT_NE(std::string(error.what()).find("scene file '" + path + "': cannot be opened"), std::string::npos);
    }
}

TEST(SceneJson, InvalidUtf8NamesCannotBeWritten) {
    Scene scene;
    scene.name = "bad \xff name";
    EXPECT_THROW(scene_to_json(scene), SceneError);
}

// Any input either parses or throws SceneError: never another exception, never a crash.
void expect_parses_or_scene_error(const std::string& text) {
    try {
        scene_from_json(text);
    } catch (const SceneError&) {
    }
}

TEST(SceneJson, TruncatedAndCorruptedInputNeverCrashes) {
    Scene small = full_scene();
    small.bodies.resize(3);
    small.constraints.resize(2);
    const std::string text = scene_to_json(small);
    for (size_t length = 0; length < text.size(); ++length) expect_parses_or_scene_error(text.substr(0, length));

    std::mt19937 rng(20240601);
    const std::string alphabet = "{}[]\",:0123456789.-+eE truefalsnl\\\x01\xff";
    for (int trial = 0; trial < 3000; ++trial) {
        std::string corrupted = text;
        const int flips = 1 + static_cast<int>(rng() % 4);
        for (int f = 0; f < flips; ++f) corrupted[rng() % corrupted.size()] = alphabet[rng() % alphabet.size()];
        expect_parses_or_scene_error(corrupted);
    }
}

}  // namespace
}  // namespace mwb

namespace mwb {
namespace {

// The one rule for which bodies the simulation moves; the add-on asks it through the module.
TEST(BodyRoles, OnlyActiveEnabledBodiesNotAnimatedThroughoutAreSimulated) {
    Body body;
    body.type = BodyType::Active;
    EXPECT_EQ(body_role(body), BodyRole::Simulated);
    body.enabled = false;
    EXPECT_EQ(body_role(body), BodyRole::Disabled);
    body.kinematic = true;
    EXPECT_EQ(body_role(body), BodyRole::Animated);
    body.type = BodyType::Passive;
    EXPECT_EQ(body_role(body), BodyRole::Animated);
    body.kinematic = false;
    body.enabled = true;
    EXPECT_EQ(body_role(body), BodyRole::Static);
}

}  // namespace
}  // namespace mwb
