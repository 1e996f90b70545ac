#pragma once
// Exponential and logarithm maps between unit quaternions (w, x, y, z) and rotation vectors
// (axis times angle, radians), plus a rotation distance that stays accurate for tiny angles.
#include <cmath>

#include "common/PortableMath.h"
#include "common/Math.h"

namespace mwb {

/// Unit quaternion of the rotation by |v| radians about v / |v|.
inline Quat quat_exp(const Vec3& v) {
    const double angle = norm(v);
    // sin(x)/x stays accurate for small x > 0; at 0 the limit 1/2 is exact.
    const double s = angle > 0 ? portable::sin(angle / 2) / angle : 0.5;
    return {portable::cos(angle / 2), v[0] * s, v[1] * s, v[2] * s};
}

/// Rotation vector of the unit quaternion q, with angle in [0, pi]; q and -q give the same result.
inline Vec3 quat_log(const Quat& q) {
    const double sign = q[0] < 0 ? -1.0 : 1.0;
    const Vec3 v{sign * q[1], sign * q[2], sign * q[3]};
    const double s = norm(v);
    if (s == 0) return {0, 0, 0};
    // atan2 keeps full relative precision for both tiny and near-pi angles, unlike acos.
    return scale(v, 2.0 * portable::atan2(s, sign * q[0]) / s);
}

/// Angle in radians, in [0, pi], of the rotation taking unit quaternion b to a; q and -q are the
/// same rotation.
inline double rotation_angle_between(const Quat& a, const Quat& b) {
    const Quat r = quat_multiply(a, quat_conjugate(b));
    return 2.0 * portable::atan2(norm(Vec3{r[1], r[2], r[3]}), std::fabs(r[0]));
}

}  // namespace mwb
