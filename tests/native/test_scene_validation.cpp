#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "scene/SceneValidation.h"

namespace mwb {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Shape cube_mesh(ShapeType type) {
    Shape s;
    s.type = type;
    for (int i = 0; i < 8; ++i) s.vertices_m.insert(s.vertices_m.end(), {i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
    if (type == ShapeType::Mesh)
        s.triangles = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                       2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    return s;
}

Body body(const std::string& name, BodyType type, Shape shape) {
    Body b;
    b.name = name;
    b.type = type;
    b.shape = std::move(shape);
    return b;
}

// Valid: an active box, a passive mesh, an animated body, an active compound and hull, and joints.
Scene base_scene() {
    Scene scene;
    scene.name = "base";
    scene.bodies.push_back(body("Cube", BodyType::Active, Shape{}));
    scene.bodies.push_back(body("Ground", BodyType::Passive, cube_mesh(ShapeType::Mesh)));
    Body lift = body("Lift", BodyType::Passive, Shape{});
    lift.kinematic = true;
    lift.animation.times_s = {0, 0.5, 1};
    lift.animation.transforms.resize(3);
    scene.bodies.push_back(lift);
    Shape compound;
    compound.type = ShapeType::Compound;
    Shape ball;
    ball.type = ShapeType::Sphere;
    ball.offset.location = {0, 0, 1};
    compound.children = {Shape{}, ball};
    scene.bodies.push_back(body("Dumbbell", BodyType::Active, compound));
    scene.bodies.push_back(body("Rock", BodyType::Active, cube_mesh(ShapeType::ConvexHull)));

    Constraint hinge;
    hinge.name = "Hinge";
    hinge.type = ConstraintType::Hinge;
    hinge.body_a = "Cube";
    hinge.body_b = "Dumbbell";
    scene.constraints.push_back(hinge);
    Constraint ball_joint;
    ball_joint.name = "Ball";
    ball_joint.type = ConstraintType::Generic;
    ball_joint.body_a = "Rock";
    ball_joint.linear_limits.enabled = {true, true, true};
    ball_joint.angular_limits.enabled = {true, false, true};
    ball_joint.angular_limits.lower = {-0.5, 0, -1};
    ball_joint.angular_limits.upper = {0.5, 0, 1};
    scene.constraints.push_back(ball_joint);
    return scene;
}

Body& find(Scene& s, const std::string& name) { return s.bodies[static_cast<size_t>(s.body_index(name))]; }

std::string joined(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines) text += line + "\n";
    return text;
}

TEST(SceneValidation, BaseSceneIsValid) { EXPECT_EQ(joined(validate_scene(base_scene())), ""); }

struct Case {
    const char* what;
    std::function<void(Scene&)> mutate;
    std::vector<std::string> expected;  // substrings of a single problem line
};

// Each case breaks one rule; one problem line must name the object and the field.
const std::vector<Case>& cases() {
    static const std::vector<Case> all{
        {"empty body name", [](Scene& s) { s.bodies[0].name = ""; }, {"body #0 (no name)", "name must not be empty"}},
        {"duplicate body name", [](Scene& s) { s.bodies[1].name = "Cube"; }, {"body 'Cube'", "name is used by bodies[0] and bodies[1]"}},
        {"nan location", [](Scene& s) { s.bodies[0].initial.location[1] = kNaN; }, {"body 'Cube'", "initial.location[1]", "finite"}},
        {"inf rotation", [](Scene& s) { s.bodies[0].initial.rotation[0] = kInf; }, {"body 'Cube'", "initial.rotation[0]", "finite"}},
        {"nan velocity", [](Scene& s) { s.bodies[0].initial_linear_velocity[2] = kNaN; }, {"body 'Cube'", "initial_linear_velocity[2]"}},
        {"nan spin", [](Scene& s) { s.bodies[0].initial_angular_velocity[0] = kInf; }, {"body 'Cube'", "initial_angular_velocity[0]"}},
        {"nan mass", [](Scene& s) { s.bodies[1].mass_kg = kNaN; }, {"body 'Ground'", "mass_kg", "finite"}},
        {"zero mass", [](Scene& s) { s.bodies[0].mass_kg = 0; }, {"body 'Cube'", "mass_kg must be > 0 for an ACTIVE body, got 0"}},
        {"negative friction", [](Scene& s) { s.bodies[0].friction = -0.1; }, {"body 'Cube'", "friction must be >= 0, got -0.1"}},
        {"negative restitution", [](Scene& s) { s.bodies[0].restitution = -1; }, {"body 'Cube'", "restitution"}},
        {"negative margin", [](Scene& s) { s.bodies[0].collision_margin_m = -0.01; }, {"body 'Cube'", "collision_margin_m"}},
        {"negative damping", [](Scene& s) { s.bodies[0].linear_damping = -0.5; }, {"body 'Cube'", "linear_damping must be between 0 and 1"}},
        {"damping above 1", [](Scene& s) { s.bodies[0].angular_damping = 1.5; }, {"body 'Cube'", "angular_damping", "1.5"}},
        {"non-unit quaternion", [](Scene& s) { s.bodies[0].initial.rotation = {1, 0, 0, 0.01}; },
         {"body 'Cube'", "initial.rotation", "unit quaternion", "1e-6"}},
        {"nan centre of mass", [](Scene& s) { s.bodies[0].has_center_of_mass = true; s.bodies[0].center_of_mass_local_m[0] = kNaN; },
         {"body 'Cube'", "center_of_mass_local_m[0]"}},
        {"line box", [](Scene& s) { s.bodies[0].shape.half_extents_m[1] = s.bodies[0].shape.half_extents_m[2] = 0; },
         {"body 'Cube'", "shape.half_extents_m has more than one side of length 0"}},
        {"negative box", [](Scene& s) { s.bodies[0].shape.half_extents_m[2] = -1; }, {"body 'Cube'", "shape.half_extents_m[2] must be >= 0"}},
        {"negative radius", [](Scene& s) { find(s, "Dumbbell").shape.children[1].radius_m = -1; },
         {"body 'Dumbbell'", "shape.children[1].radius_m must be > 0"}},
        {"nan cylinder height",
         [](Scene& s) { s.bodies[0].shape = Shape{}; s.bodies[0].shape.type = ShapeType::Cylinder; s.bodies[0].shape.height_m = kNaN; },
         {"body 'Cube'", "shape.height_m", "finite"}},
        {"short capsule",
         [](Scene& s) { s.bodies[0].shape.type = ShapeType::Capsule; s.bodies[0].shape.height_m = 0.5; },
         {"body 'Cube'", "shape.height_m", "2 * radius_m"}},
        {"zero cone", [](Scene& s) { s.bodies[0].shape.type = ShapeType::Cone; s.bodies[0].shape.radius_m = 0; },
         {"body 'Cube'", "shape.radius_m"}},
        {"hull with 3 points", [](Scene& s) { find(s, "Rock").shape.vertices_m.resize(9); },
         {"body 'Rock'", "shape.vertices_m", "at least 4 points"}},
        {"hull on a line", [](Scene& s) { auto& v = find(s, "Rock").shape.vertices_m; for (size_t i = 0; i < v.size(); ++i) if (i % 3) v[i] = 0; },
         {"body 'Rock'", "shape.vertices_m", "no volume"}},
        {"hull not (n, 3)", [](Scene& s) { find(s, "Rock").shape.vertices_m.push_back(1); }, {"body 'Rock'", "shape.vertices_m", "(n, 3)"}},
        {"nan hull point", [](Scene& s) { find(s, "Rock").shape.vertices_m[7] = kNaN; }, {"body 'Rock'", "shape.vertices_m[7]"}},
        {"mesh without triangles", [](Scene& s) { s.bodies[1].shape.triangles.clear(); }, {"body 'Ground'", "shape.triangles is empty"}},
        {"mesh index out of range", [](Scene& s) { s.bodies[1].shape.triangles[4] = 8; },
         {"body 'Ground'", "shape.triangles[4] = 8 is out of range (8 vertices)"}},
        {"mesh vertices not (n, 3)", [](Scene& s) { s.bodies[1].shape.vertices_m.pop_back(); }, {"body 'Ground'", "shape.vertices_m", "(n, 3)"}},
        {"mesh triangles not (m, 3)", [](Scene& s) { s.bodies[1].shape.triangles.pop_back(); }, {"body 'Ground'", "shape.triangles", "(m, 3)"}},
        {"degenerate mesh", [](Scene& s) { s.bodies[1].shape.triangles = {0, 1, 1, 2, 2, 2}; },
         {"body 'Ground'", "shape.triangles", "degenerate"}},
        {"mesh on an active body", [](Scene& s) { s.bodies[0].shape = cube_mesh(ShapeType::Mesh); },
         {"body 'Cube'", "shape is a MESH", "use CONVEX_HULL for active bodies; triangle meshes collide only as passive/animated bodies"}},
        {"mesh inside an active compound", [](Scene& s) { find(s, "Dumbbell").shape.children[0] = cube_mesh(ShapeType::Mesh); },
         {"body 'Dumbbell'", "shape.children[0] is a MESH", "use CONVEX_HULL"}},
        {"empty compound", [](Scene& s) { find(s, "Dumbbell").shape.children.clear(); }, {"body 'Dumbbell'", "shape.children is empty"}},
        {"compound child offset", [](Scene& s) { find(s, "Dumbbell").shape.children[1].offset.rotation = {2, 0, 0, 0}; },
         {"body 'Dumbbell'", "shape.children[1].offset.rotation", "unit quaternion"}},
        {"animation lengths", [](Scene& s) { find(s, "Lift").animation.times_s.pop_back(); },
         {"body 'Lift'", "animation has 2 times_s but 3 transforms"}},
        {"animation times", [](Scene& s) { find(s, "Lift").animation.times_s[2] = 0.5; },
         {"body 'Lift'", "animation.times_s[2] must be greater than the previous time"}},
        {"animation nan", [](Scene& s) { find(s, "Lift").animation.transforms[1].location[0] = kNaN; },
         {"body 'Lift'", "animation.transforms[1].location[0]"}},
        {"variation min > max", [](Scene& s) { s.bodies[0].variation.location_min_m[1] = 0.5; },
         {"body 'Cube'", "variation.location_min_m[1] (0.5) is greater than variation.location_max_m[1] (0)"}},
        {"variation nan", [](Scene& s) { s.bodies[0].variation.angular_velocity_max[2] = kNaN; },
         {"body 'Cube'", "variation.angular_velocity_max[2]", "finite"}},
        {"variation scale", [](Scene& s) { s.bodies[0].variation.friction_scale_min = 2; },
         {"body 'Cube'", "variation.friction_scale_min (2) is greater than variation.friction_scale_max (1)"}},
        {"variation mass scale", [](Scene& s) { s.bodies[0].variation.mass_scale_min = 0; },
         {"body 'Cube'", "variation.mass_scale_min must be > 0"}},
        {"missing constraint body", [](Scene& s) { s.constraints[0].body_b = "Nope"; },
         {"constraint 'Hinge'", "body_b 'Nope' is not a body in the scene"}},
        {"constraint without bodies", [](Scene& s) { s.constraints[0].body_a = s.constraints[0].body_b = ""; },
         {"constraint 'Hinge'", "body_a/body_b are both empty"}},
        {"constraint to itself", [](Scene& s) { s.constraints[0].body_b = "Cube"; },
         {"constraint 'Hinge'", "body_a/body_b are both 'Cube'", "constrained to itself"}},
        {"unnamed constraint", [](Scene& s) { s.constraints[1].name = ""; }, {"constraint #1 (no name)", "name must not be empty"}},
        {"constraint frame", [](Scene& s) { s.constraints[0].frame.location[2] = kInf; }, {"constraint 'Hinge'", "frame.location[2]"}},
        {"limits reversed", [](Scene& s) { s.constraints[1].angular_limits.lower[0] = 1; },
         {"constraint 'Ball'", "angular_limits.lower[0] (1) is greater than angular_limits.upper[0] (0.5)"}},
        {"negative spring", [](Scene& s) { s.constraints[0].angular_springs.stiffness[1] = -3; },
         {"constraint 'Hinge'", "angular_springs.stiffness[1] must be >= 0"}},
        {"negative breaking threshold", [](Scene& s) { s.constraints[0].breaking_threshold = -1; }, {"constraint 'Hinge'", "breaking_threshold"}},
        {"negative motor impulse", [](Scene& s) { s.constraints[0].motor_angular_max_impulse = -1; },
         {"constraint 'Hinge'", "motor_angular_max_impulse"}},
        {"generic with free axis", [](Scene& s) { s.constraints[1].linear_limits.enabled[2] = false; },
         {"constraint 'Ball': GENERIC with free or limited linear axes is not supported by the ODE engine; lock all linear axes",
          "SLIDER/PISTON"}},
        {"generic spring with limited axis",
         [](Scene& s) { s.constraints[1].type = ConstraintType::GenericSpring; s.constraints[1].linear_limits.upper[0] = 0.1; },
         {"constraint 'Ball': GENERIC_SPRING with free or limited linear axes is not supported"}},
        {"substeps", [](Scene& s) { s.world.substeps_per_frame = 0; }, {"world: substeps_per_frame must be >= 1, got 0"}},
        {"solver iterations", [](Scene& s) { s.world.solver_iterations = -2; }, {"world: solver_iterations must be >= 1, got -2"}},
        {"fps", [](Scene& s) { s.world.fps = 0; }, {"world: fps must be > 0, got 0"}},
        {"frame range", [](Scene& s) { s.world.frame_end = 0; }, {"world: frame_end (0) must not be before frame_start (1)"}},
        {"time scale", [](Scene& s) { s.world.time_scale = -1; }, {"world: time_scale must be > 0, got -1"}},
        {"gravity", [](Scene& s) { s.world.gravity[2] = kNaN; }, {"world: gravity[2] must be a finite number"}},
    };
    return all;
}

TEST(SceneValidation, EveryRuleNamesTheObjectAndField) {
    for (const Case& c : cases()) {
        Scene scene = base_scene();
        c.mutate(scene);
        const std::vector<std::string> problems = validate_scene(scene);
        bool found = false;
        for (const std::string& line : problems) {
            bool all = true;
            for (const std::string& part : c.expected) all = all && line.find(part) != std::string::npos;
            found = found || all;
        }
        EXPECT_TRUE(found) << c.what << ": no line contains all of the expected parts; got:\n" << joined(problems);
    }
}

TEST(SceneValidation, ReportsEveryProblemAtOnce) {
    Scene scene = base_scene();
    scene.bodies[0].mass_kg = -1;
    scene.bodies[0].friction = -1;
    scene.bodies[1].shape.triangles.clear();
    scene.constraints[0].body_a = "Ghost";
    scene.world.fps = 0;
    EXPECT_EQ(validate_scene(scene).size(), 5u) << joined(validate_scene(scene));
}

TEST(SceneValidation, AllowedEdgeCases) {
    Scene scene = base_scene();
    scene.bodies[1].mass_kg = 0;                             // passive bodies need no mass
    find(scene, "Lift").shape = cube_mesh(ShapeType::Mesh);  // animated meshes collide fine
    find(scene, "Lift").type = BodyType::Active;
    scene.constraints[0].body_b = "";                        // constrained to the world
    scene.world.frame_end = scene.world.frame_start;
    scene.bodies[0].initial.rotation = {1 + 5e-7, 0, 0, 0};  // within the 1e-6 tolerance
    EXPECT_EQ(joined(validate_scene(scene)), "");
}

}  // namespace
}  // namespace mwb
