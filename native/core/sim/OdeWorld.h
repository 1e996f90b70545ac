#pragma once
// One ODE world built from a compiled scene and a world's initial conditions; it owns every ODE
// object of that world. Each world has its own threading implementation: ODE's shared default one
// has fake locks and aborts when two worlds step on two threads.
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include <ode/ode.h>

#include "sim/BodyInitialState.h"
#include "sim/CompiledScene.h"
#include "sim/ConstraintBuilder.h"
#include "sim/WorldResult.h"

namespace mwb {

/// ODE error handlers that turn ODE's abort() into a C++ exception; installed once per process.
void initialize_ode_once();
/// ODE needs per-thread collision data; call on every thread before it touches a world.
void prepare_ode_thread();

struct OdeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// An ODE vector (body position, velocity, contact point) as a Vec3.
inline Vec3 from_ode(const dReal* v) { return {v[0], v[1], v[2]}; }

/// What a geom belongs to; the geom's user data is its index in OdeWorld::geom_owners().
struct GeomOwner {
    int32_t body = -1;
    bool is_mesh = false;
    bool ghost = false;  ///< a refinement ghost of `body`: detects contacts, never makes any
    double mesh_margin_m = 0;  ///< a triangle mesh thickened by Blender's collision margin
};

/// Not thread-safe: one thread at a time per world, after prepare_ode_thread() on that thread.
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
    dJointGroupID contact_group() const { return contact_group_; }
    /// ODE body per scene body; null for static passive bodies.
    const std::vector<dBodyID>& bodies() const { return bodies_; }
    /// Per scene constraint; a constraint this world does not have holds no joints.
    const std::vector<JointGroup>& joint_groups() const { return joint_groups_; }
    const std::vector<GeomOwner>& geom_owners() const { return geom_owners_; }
    /// Every geom, in no space (ContactGenerator finds their pairs), ghosts' last; geom i belongs
    /// to geom_owners()[i].
    const std::vector<dGeomID>& geoms() const { return geoms_; }
    /// True if the scene's constraints ask that bodies a and b never collide.
    bool collision_disabled(int32_t a, int32_t b) const;
    const std::vector<BodyInitialState>& initial_states() const { return initial_; }

    /// Centre-of-mass state of body i (dynamic or kinematic).
    BodyState body_state(size_t i) const;
    void set_body_state(size_t i, const BodyState& state);
    /// Sets the centre-of-mass state of body i's refinement ghost (add_ghost(i) first).
    void set_ghost_state(size_t i, const BodyState& state);
    /// Object-origin transform of body i right now.
    Transform object_transform(size_t i) const;

    /// Refinement: a body stops being simulated and follows given poses, or starts again.
    void set_kinematic(size_t i, bool kinematic);
    /// Refinement: adds a non-colliding, slightly grown copy of body i that follows given poses
    /// (set with set_ghost_state(i, ...)).
    void add_ghost(size_t i);
    /// Ghosts of earlier refinements leave collision detection; a later one may bring them back.
    void set_ghost_enabled(size_t i, bool enabled);

    /// Disables every joint of constraint `constraint_index` for good.
    void break_joint(size_t constraint_index);
    /// Breaks the breakable constraints whose joint impulse in the last step (force × physics
    /// step) exceeded their breaking threshold, N·s.
    void break_overloaded_joints();

private:
    void create_bodies();
    void create_geoms(size_t body_index, const std::vector<CollisionPart>& parts, dBodyID body, bool ghost);
    void create_constraints();
    bool is_present(int body) const { return body < 0 || present_.empty() || present_[static_cast<size_t>(body)]; }

    const CompiledScene& compiled_;
    std::vector<BodyInitialState> initial_;
    std::vector<uint8_t> present_;
    dThreadingImplementationID threading_ = nullptr;
    dWorldID world_ = nullptr;
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
