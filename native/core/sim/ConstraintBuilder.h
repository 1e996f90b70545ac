#pragma once
// Maps Blender's rigid-body constraint types onto ODE joints. Blender measures hinge angles and
// slider positions from the pose at the start of the simulation, as ODE does from joint creation.
#include <memory>
#include <vector>

#include <ode/ode.h>

#include "scene/Scene.h"

namespace mwb {

/// ODE joints making up one scene constraint (a generic constraint is a ball plus an angular motor).
struct JointGroup {
    std::vector<dJointID> joints;
    std::unique_ptr<dJointFeedback> feedback;  ///< on joints[0], only for breakable constraints
    /// Breakable constraints: the constraint's frame in joints[0]'s first body's frame (centre of
    /// mass), to read the feedback along the constraint's own axes as the body moves.
    Transform frame_in_body;
    bool broken = false;
};

/// Creates the joints of constraint `c` in `world` between the ODE bodies of its objects A and B
/// (null for a static object), measuring limits from the bodies' poses now. `step_s` is the
/// physics time of one step, seconds (springs and motor impulses depend on it). Both bodies null:
/// nothing can move, and the group has no joints.
JointGroup build_constraint_joints(dWorldID world, const Constraint& c, dBodyID a, dBodyID b, double step_s);

}  // namespace mwb
