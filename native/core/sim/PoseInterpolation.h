#pragma once
// Poses between keys, and the velocities that carry a body from one pose to the next: shared by
// animated bodies and by bodies that replay a recorded world.
#include "scene/Scene.h"
#include "sim/WorldResult.h"

namespace mwb {

/// The pose a fraction `u` in [0, 1] of the way from `a` to `b`: linear in position,
/// normalized-linear in rotation (the shorter way round).
Transform interpolate_pose(const Transform& a, const Transform& b, double u);

/// The pose of `track` at `time_s`, held before its first key and after its last; `fallback` when
/// the track has no keys.
Transform sample_animation(const KinematicTrack& track, double time_s, const Transform& fallback);

/// World-frame angular velocity (rad/s) that turns rotation `q0` into `q1` in `dt_s` seconds.
Vec3 angular_velocity_between(const Quat& q0, const Quat& q1, double dt_s);

/// Centre-of-mass state of a body whose object origin is at `now` and reaches `next` after `dt_s`
/// seconds of physics time; `com_offset_m` is its centre of mass in the object frame.
BodyState state_moving_between(const Transform& now, const Transform& next, const Vec3& com_offset_m, double dt_s);

}  // namespace mwb
