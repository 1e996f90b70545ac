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

void sample_recorded_poses(const double* positions, const double* orientations, size_t bodies, size_t frames,
                           const std::vector<double>& at_frames, double* out_positions, double* out_orientations) {
    if (frames == 0) return;
    std::vector<Transform> track(frames);
    for (size_t b = 0; b < bodies; ++b) {
        const double* p = positions + b * frames * 3;
        const double* q = orientations + b * frames * 4;
        // Sign-continuous: each key on the hemisphere of the one before it as recorded.
        double sign = 1;
        for (size_t f = 0; f < frames; ++f) {
            if (f > 0 && q[f * 4] * q[f * 4 - 4] + q[f * 4 + 1] * q[f * 4 - 3] + q[f * 4 + 2] * q[f * 4 - 2] +
                                 q[f * 4 + 3] * q[f * 4 - 1] < 0)
                sign = -sign;
            track[f].location = {p[f * 3], p[f * 3 + 1], p[f * 3 + 2]};
            track[f].rotation = {sign * q[f * 4], sign * q[f * 4 + 1], sign * q[f * 4 + 2], sign * q[f * 4 + 3]};
        }
        for (size_t k = 0; k < at_frames.size(); ++k) {
            const double at = std::clamp(at_frames[k], 0.0, static_cast<double>(frames - 1));
            const auto lo = static_cast<size_t>(std::floor(at));
            const size_t hi = std::min(lo + 1, frames - 1);
            const Transform t = interpolate_pose(track[lo], track[hi], at - static_cast<double>(lo));
            double* op = out_positions + (b * at_frames.size() + k) * 3;
            double* oq = out_orientations + (b * at_frames.size() + k) * 4;
            for (int a = 0; a < 3; ++a) op[a] = t.location[a];
            for (int a = 0; a < 4; ++a) oq[a] = t.rotation[a];
        }
    }
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
