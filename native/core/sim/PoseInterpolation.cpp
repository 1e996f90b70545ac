#include "sim/PoseInterpolation.h"

#include <algorithm>
#include <cmath>

#include "common/PortableMath.h"

namespace mwb {

Transform interpolate_pose(const Transform& a, const Transform& b, double u) {
    Quat qb = b.rotation;
    if (a.rotation[0] * qb[0] + a.rotation[1] * qb[1] + a.rotation[2] * qb[2] + a.rotation[3] * qb[3] < 0)
        qb = {-qb[0], -qb[1], -qb[2], -qb[3]};
    Quat q;
    for (int k = 0; k < 4; ++k) q[k] = a.rotation[k] + (qb[k] - a.rotation[k]) * u;
    return {add(a.location, scale(sub(b.location, a.location), u)), quat_normalized(q)};
}

Transform sample_animation(const KinematicTrack& track, double time_s, const Transform& fallback) {
    if (track.times_s.empty()) return fallback;
    if (time_s <= track.times_s.front()) return track.transforms.front();
    if (time_s >= track.times_s.back()) return track.transforms.back();
    const size_t hi = static_cast<size_t>(std::upper_bound(track.times_s.begin(), track.times_s.end(), time_s) -
                                          track.times_s.begin());
    const size_t lo = hi - 1;
    const double u = (time_s - track.times_s[lo]) / (track.times_s[hi] - track.times_s[lo]);
    return interpolate_pose(track.transforms[lo], track.transforms[hi], u);
}

Vec3 angular_velocity_between(const Quat& q0, const Quat& q1, double dt_s) {
    Quat d = quat_multiply(q1, quat_conjugate(q0));
    if (d[0] < 0) d = {-d[0], -d[1], -d[2], -d[3]};
    const Vec3 v{d[1], d[2], d[3]};
    const double s = norm(v);
    if (s < 1e-15) return {0, 0, 0};
    const double angle = 2 * portable::atan2(s, d[0]);
    return scale(v, angle / (s * dt_s));
}

BodyState state_moving_between(const Transform& now, const Transform& next, const Vec3& com_offset_m, double dt_s) {
    const Vec3 com_now = add(now.location, quat_rotate(now.rotation, com_offset_m));
    const Vec3 com_next = add(next.location, quat_rotate(next.rotation, com_offset_m));
    return {com_now, now.rotation, scale(sub(com_next, com_now), 1.0 / dt_s),
            angular_velocity_between(now.rotation, next.rotation, dt_s)};
}

}  // namespace mwb
