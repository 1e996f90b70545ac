#pragma once
// The scene model: what Blender's rigid-body settings say, in Blender's units (metres, kilograms,
// seconds, Z up). Object transforms are the object's origin; the simulation works at the centre of
// mass and converts back. Nothing here depends on ODE, Python or Blender.
#include <cstdint>
#include <string>
#include <vector>

#include "common/Math.h"

namespace mwb {

enum class ShapeType { Box, Sphere, Capsule, Cylinder, Cone, ConvexHull, Mesh, Compound };
enum class BodyType { Active, Passive };
enum class ConstraintType { Fixed, Point, Hinge, Slider, Piston, Generic, GenericSpring, Motor };

struct Transform {
    Vec3 location{0, 0, 0};
    Quat rotation{1, 0, 0, 0};  ///< unit quaternion (w, x, y, z)
};

/// A collision shape in its owner's local frame. Capsule, cylinder and cone run along local Z
/// (Blender's convention); `height_m` is the full length including capsule caps.
struct Shape {
    ShapeType type = ShapeType::Box;
    Vec3 half_extents_m{0.5, 0.5, 0.5};  ///< Box
    double radius_m = 0.5;               ///< Sphere, Capsule, Cylinder, Cone
    double height_m = 1.0;               ///< Capsule, Cylinder, Cone
    std::vector<double> vertices_m;      ///< ConvexHull, Mesh: flat (n, 3)
    std::vector<uint32_t> triangles;     ///< Mesh: flat (m, 3) vertex indices
    Transform offset;                    ///< placement inside a Compound parent
    std::vector<Shape> children;         ///< Compound
};

/// Uniform variation ranges applied to a body's initial state, [min, max] per axis.
struct VariationRanges {
    Vec3 location_min_m{0, 0, 0}, location_max_m{0, 0, 0};
    Vec3 rotation_min_rad{0, 0, 0}, rotation_max_rad{0, 0, 0};  ///< XYZ Euler, added to the pose
    Vec3 linear_velocity_min{0, 0, 0}, linear_velocity_max{0, 0, 0};      ///< m/s, world frame
    Vec3 angular_velocity_min{0, 0, 0}, angular_velocity_max{0, 0, 0};    ///< rad/s, world frame
    double mass_scale_min = 1, mass_scale_max = 1;
    double friction_scale_min = 1, friction_scale_max = 1;
    double restitution_scale_min = 1, restitution_scale_max = 1;
};

/// Sampled animation of a kinematic ("Animated") passive body: origin transform over time.
struct KinematicTrack {
    std::vector<double> times_s;
    std::vector<Transform> transforms;
};

struct Body {
    std::string name;
    /// The scene object this body stands for, when that is not `name`: a library scene keeps an
    /// object's earlier definitions after it changed, each under its own body name.
    std::string object;
    BodyType type = BodyType::Active;
    bool kinematic = false;  ///< Blender's "Animated": follows `animation` instead of physics
    /// > 0: "Animated" keyed off at this time (seconds from the first frame). Until then the body
    /// follows `animation`; from then on it is simulated, leaving with the animation's velocity.
    double animated_until_s = 0;
    bool enabled = true;     ///< Blender's "Dynamic" toggle; disabled active bodies stay put
    Shape shape;
    double mass_kg = 1.0;
    double friction = 0.5;
    double restitution = 0.0;
    bool use_margin = false;
    double collision_margin_m = 0.04;
    double linear_damping = 0.04;   ///< fraction of velocity lost per second (Blender/Bullet)
    double angular_damping = 0.1;
    /// Blender's Rigid Body > Dynamics > Deactivation (Bullet's sleeping): when enabled, the body
    /// sleeps below these speeds (after Bullet's 2 s), and with start_deactivated it starts
    /// asleep, until something reaches it.
    struct Deactivation {
        bool enabled = false;
        bool start_deactivated = false;
        double linear_speed = 0.4;   ///< m/s
        double angular_speed = 0.5;  ///< rad/s
    } deactivation;
    uint32_t collision_collections = 1;  ///< bit i set: member of Blender collision collection i
    Transform initial;
    Vec3 initial_linear_velocity{0, 0, 0};
    Vec3 initial_angular_velocity{0, 0, 0};
    bool has_center_of_mass = false;  ///< else computed from the shape at uniform density
    Vec3 center_of_mass_local_m{0, 0, 0};
    KinematicTrack animation;
    VariationRanges variation;
};

/// Per-axis settings of a constraint, axes X, Y, Z in the constraint frame.
struct AxisLimits {
    std::array<bool, 3> enabled{false, false, false};
    Vec3 lower{0, 0, 0};  ///< metres for linear axes, radians for angular axes
    Vec3 upper{0, 0, 0};
};
struct AxisSprings {
    std::array<bool, 3> enabled{false, false, false};
    Vec3 stiffness{10, 10, 10};
    Vec3 damping{0.5, 0.5, 0.5};
};

struct Constraint {
    std::string name;
    ConstraintType type = ConstraintType::Fixed;
    std::string body_a, body_b;
    bool enabled = true;
    bool disable_collisions = true;
    Transform frame;  ///< world-space pivot; hinge turns about frame Z, slider/piston/motor use X
    bool breakable = false;
    double breaking_threshold = 10.0;  ///< impulse, N·s
    AxisLimits linear_limits, angular_limits;
    AxisSprings linear_springs, angular_springs;
    bool motor_linear_enabled = false, motor_angular_enabled = false;
    double motor_linear_target_velocity = 1.0;   ///< m/s
    double motor_linear_max_impulse = 1.0;       ///< N·s per step
    double motor_angular_target_velocity = 1.0;  ///< rad/s
    double motor_angular_max_impulse = 1.0;
};

struct WorldSettings {
    Vec3 gravity{0, 0, -9.81};
    double time_scale = 1.0;
    int substeps_per_frame = 10;
    int solver_iterations = 10;
    int frame_start = 1;
    int frame_end = 250;
    double fps = 24.0;
};

/// What the simulation does with a body, the one rule every front end asks for.
enum class BodyRole {
    Simulated,  ///< ACTIVE, "Dynamic" on, not animated throughout: moved by physics (and perturbed)
    Animated,   ///< "Animated" throughout: follows its animation
    Static,     ///< PASSIVE and not animated: never moves
    Disabled,   ///< ACTIVE with "Dynamic" off: stays where it is
};

/// The role of `body` (a body whose "Animated" is keyed off is Simulated).
BodyRole body_role(const Body& body);
const char* to_string(BodyRole role);

struct Scene {
    std::string name;
    WorldSettings world;
    std::vector<Body> bodies;
    std::vector<Constraint> constraints;

    /// Index of the body called `body_name`, or -1.
    int body_index(const std::string& body_name) const;
};

const char* to_string(ShapeType type);
const char* to_string(BodyType type);
const char* to_string(ConstraintType type);
/// Parse Blender's enum identifiers ("BOX", "CONVEX_HULL", "GENERIC_SPRING", ...); false if unknown.
bool parse_shape_type(const std::string& text, ShapeType& out);
bool parse_body_type(const std::string& text, BodyType& out);
bool parse_constraint_type(const std::string& text, ConstraintType& out);

}  // namespace mwb
