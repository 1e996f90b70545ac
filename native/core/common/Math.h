#pragma once
// Small fixed-size vector and rotation helpers shared by the core. Quaternions are (w, x, y, z).
#include <array>
#include <cmath>

#include "common/PortableMath.h"

namespace mwb {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;

inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

inline Quat quat_multiply(const Quat& a, const Quat& b) {
    return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
inline Quat quat_conjugate(const Quat& q) { return {q[0], -q[1], -q[2], -q[3]}; }
inline Quat quat_normalized(const Quat& q) {
    double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
}
/// Rotates v by the unit quaternion q.
inline Vec3 quat_rotate(const Quat& q, const Vec3& v) {
    Vec3 u{q[1], q[2], q[3]};
    Vec3 t = scale(cross(u, v), 2.0);
    return add(add(v, scale(t, q[0])), cross(u, t));
}
/// Rotation of `angle_rad` about the unit `axis`.
inline Quat quat_from_axis_angle(const Vec3& axis, double angle_rad) {
    double s = portable::sin(angle_rad / 2);
    return {portable::cos(angle_rad / 2), axis[0] * s, axis[1] * s, axis[2] * s};
}
/// Blender's default XYZ Euler order: R = Rz * Ry * Rx.
inline Quat quat_from_euler_xyz(const Vec3& euler_rad) {
    Quat qx = quat_from_axis_angle({1, 0, 0}, euler_rad[0]);
    Quat qy = quat_from_axis_angle({0, 1, 0}, euler_rad[1]);
    Quat qz = quat_from_axis_angle({0, 0, 1}, euler_rad[2]);
    return quat_multiply(qz, quat_multiply(qy, qx));
}
/// Angle in radians of the rotation taking a to b, in [0, pi].
/// The rotation whose matrix has columns x, y, z (orthonormal, right-handed).
inline Quat quat_from_axes(const Vec3& x, const Vec3& y, const Vec3& z) {
    const double trace = x[0] + y[1] + z[2];
    Quat q;
    if (trace > 0) {
        const double s = 2 * std::sqrt(1 + trace);
        q = {s / 4, (y[2] - z[1]) / s, (z[0] - x[2]) / s, (x[1] - y[0]) / s};
    } else if (x[0] > y[1] && x[0] > z[2]) {
        const double s = 2 * std::sqrt(1 + x[0] - y[1] - z[2]);
        q = {(y[2] - z[1]) / s, s / 4, (y[0] + x[1]) / s, (z[0] + x[2]) / s};
    } else if (y[1] > z[2]) {
        const double s = 2 * std::sqrt(1 + y[1] - x[0] - z[2]);
        q = {(z[0] - x[2]) / s, (y[0] + x[1]) / s, s / 4, (z[1] + y[2]) / s};
    } else {
        const double s = 2 * std::sqrt(1 + z[2] - x[0] - y[1]);
        q = {(x[1] - y[0]) / s, (z[0] + x[2]) / s, (z[1] + y[2]) / s, s / 4};
    }
    return quat_normalized(q);
}

inline double quat_angle_between(const Quat& a, const Quat& b) {
    double d = std::fabs(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]);
    return 2.0 * portable::acos(d > 1.0 ? 1.0 : d);
}

}  // namespace mwb
