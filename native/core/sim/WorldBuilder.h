#pragma once
// Builds one ODE world from a compiled scene and a world's initial conditions, and owns every ODE
// object of it. Each world has its own threading implementation: ODE's shared default one has
// fake locks and aborts when two worlds step on two threads.
#include <memory>
#include <stdexcept>
#include <vector>

#include <ode/ode.h>

#include "sim/CompiledScene.h"
#include "sim/PortableRandom.h"
#include "sim/WorldResult.h"

namespace mwb {

/// A body's randomized starting state and material, object-origin frame.
struct BodyInitialState {
    Transform pose;
    Vec3 linear_velocity{0, 0, 0};
    Vec3 angular_velocity{0, 0, 0};
    double mass_kg = 1;
    double friction = 0.5;
    double restitution = 0;
};

/// Draws every body's initial state from its variation ranges. Always consumes the same number
/// of draws per body, so a body's draws never depend on other bodies' ranges.
std::vector<BodyInitialState> draw_initial_states(const Scene& scene, PortableRandom& random);

/// ODE error handlers that turn ODE's abort() into a C++ exception; installed once per process.
void initialize_ode_once();
/// ODE needs per-thread collision data; call on every thread before it touches a world.
void prepare_ode_thread();

struct OdeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// What a geom belongs to; the geom's user data is its index in OdeWorld::geom_owners().
struct GeomOwner {
    int32_t body = -1;
    bool is_mesh = false;
    bool ghost = false;  ///< a refinement ghost of `body`: detects contacts, never makes any
};

/// ODE joints making up one scene constraint (a generic constraint is a ball plus an angular motor).
struct JointGroup {
    std::vector<dJointID> joints;
    std::unique_ptr<dJointFeedback> feedback;  ///< on joints[0], only for breakable constraints
    bool broken = false;
};

class OdeWorld {
public:
    /// `present`: per scene body, 0 for a body this world does not have (no ODE body, no geoms,
    /// no constraints; only a ghost may stand for it). Empty: every body is present.
    OdeWorld(const CompiledScene& compiled, const std::vector<BodyInitialState>& initial,
             const std::vector<uint8_t>& present = {});
    ~OdeWorld();
    OdeWorld(const OdeWorld&) = delete;
    OdeWorld& operator=(const OdeWorld&) = delete;

    dWorldID world() const { return world_; }
    dSpaceID space() const { return space_; }
    dJointGroupID contact_group() const { return contact_group_; }
    /// ODE body per scene body; null for static passive bodies.
    const std::vector<dBodyID>& bodies() const { return bodies_; }
    std::vector<JointGroup>& joint_groups() { return joint_groups_; }
    const std::vector<GeomOwner>& geom_owners() const { return geom_owners_; }
    /// True if the scene's constraints ask that bodies a and b never collide.
    bool collision_disabled(int32_t a, int32_t b) const;
    const std::vector<BodyInitialState>& initial_states() const { return initial_; }

    /// Centre-of-mass state of body i (dynamic or kinematic).
    BodyState body_state(size_t i) const;
    void set_body_state(size_t i, const BodyState& state);
    /// Object-origin transform of body i right now.
    Transform object_transform(size_t i) const;

    /// Refinement: a body stops being simulated and follows given poses, or starts again.
    void set_kinematic(size_t i, bool kinematic);
    /// Refinement: adds a non-colliding, slightly grown copy of body i that follows given poses
    /// (set with ghost_body(i)).
    void add_ghost(size_t i);
    dBodyID ghost_body(size_t i) const { return i < ghost_bodies_.size() ? ghost_bodies_[i] : nullptr; }
    /// Ghosts of earlier refinements leave collision detection; a later one may bring them back.
    void set_ghost_enabled(size_t i, bool enabled);

private:
    void create_bodies();
    void create_geoms(size_t body_index, const std::vector<CollisionPart>& parts, dBodyID body, bool ghost);
    void create_constraints();
    void create_constraint(size_t constraint_index);
    bool is_present(int body) const { return body < 0 || present_.empty() || present_[static_cast<size_t>(body)]; }

    const CompiledScene& compiled_;
    std::vector<BodyInitialState> initial_;
    std::vector<uint8_t> present_;
    dThreadingImplementationID threading_ = nullptr;
    dWorldID world_ = nullptr;
    dSpaceID space_ = nullptr;
    dJointGroupID contact_group_ = nullptr;
    std::vector<dBodyID> bodies_;
    std::vector<dBodyID> ghost_bodies_;
    std::vector<std::vector<dGeomID>> ghost_geoms_;
    std::vector<dGeomID> geoms_;
    std::vector<dTriMeshDataID> mesh_data_;
    std::vector<GeomOwner> geom_owners_;
    std::vector<JointGroup> joint_groups_;
    std::vector<std::pair<int32_t, int32_t>> no_collision_pairs_;
};

}  // namespace mwb
