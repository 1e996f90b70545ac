#pragma once
// Poses between keys, and the velocities that carry a body from one pose to the next: shared by
// animated bodies and by bodies that replay a recorded world.
#include <cstddef>
#include <vector>

#include "scene/Scene.h"
#include "sim/WorldResult.h"

namespace mwb {

/// The pose a fraction `u` in [0, 1] of the way from `a` to `b`: linear in position,
/// normalized-linear in rotation (the shorter way round).
Transform interpolate_pose(const Transform& a, const Transform& b, double u);

/// Poses of recorded tracks at fractional frame indices `at_frames` (clamped to the recorded
/// range), as a bake keys them and a preview shows them: interpolate_pose between neighbouring
/// frames, each track's quaternions first made sign-continuous (q and -q are one rotation, but
/// keys that alternate sign swing F-curves the long way round). Row-major arrays: positions
/// (bodies, frames, 3), orientations (bodies, frames, 4) (w, x, y, z); out_positions (bodies, n, 3)
/// and out_orientations (bodies, n, 4) for n = at_frames.size(). NaN (an absent body) stays NaN.
void sample_recorded_poses(const double* positions, const double* orientations, size_t bodies, size_t frames,
                           const std::vector<double>& at_frames, double* out_positions, double* out_orientations);

/// The pose of `track` at `time_s`, held before its first key and after its last; `fallback` when
/// the track has no keys.
Transform sample_animation(const KinematicTrack& track, double time_s, const Transform& fallback);

/// World-frame angular velocity (rad/s) that turns rotation `q0` into `q1` in `dt_s` seconds.
Vec3 angular_velocity_between(const Quat& q0, const Quat& q1, double dt_s);

/// Centre-of-mass state of a body whose object origin is at `now` and reaches `next` after `dt_s`
/// seconds of physics time; `com_offset_m` is its centre of mass in the object frame.
BodyState state_moving_between(const Transform& now, const Transform& next, const Vec3& com_offset_m, double dt_s);

}  // namespace mwb
