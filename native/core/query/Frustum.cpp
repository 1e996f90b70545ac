#include "query/Frustum.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mwb {
namespace {

using Row = std::array<double, 4>;

Row row(const Matrix4& m, int r) { return {m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3]}; }

// Plane a·(x, y, z, 1) >= 0 from a clip-space inequality, normalized.
Plane plane_from(const Row& a) {
    const Vec3 n{a[0], a[1], a[2]};
    const double length = norm(n);
    if (!(length > 0) || !std::isfinite(length)) throw std::invalid_argument("query camera is singular");
    return {scale(n, 1.0 / length), a[3] / length};
}

Row combine(const Row& a, double s, const Row& b) { return {a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]}; }

}  // namespace

Matrix4 multiply(const Matrix4& a, const Matrix4& b) {
    Matrix4 out{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k) out[4 * r + c] += a[4 * r + k] * b[4 * k + c];
    return out;
}

Frustum make_screen_frustum(const Matrix4& view, const Matrix4& projection, double width, double height, double x0,
                            double y0, double x1, double y1) {
    if (!(width > 0) || !(height > 0)) throw std::invalid_argument("query viewport must have a positive size");
    if (x0 > x1) std::swap(x0, x1);
    if (y0 > y1) std::swap(y0, y1);
    if (!(x1 > x0) || !(y1 > y0)) throw std::invalid_argument("query box is empty");
    const Matrix4 m = multiply(projection, view);
    const Row rx = row(m, 0), ry = row(m, 1), rz = row(m, 2), rw = row(m, 3);
    // A point is inside when its normalized device coordinates lie in the box: for x,
    // ndc_x0 <= x_c / w_c <= ndc_x1, i.e. x_c - ndc_x0 w_c >= 0 and ndc_x1 w_c - x_c >= 0
    // (w_c > 0 in front of the camera). The same for y; near and far are -w <= z <= w.
    const double nx0 = 2 * x0 / width - 1, nx1 = 2 * x1 / width - 1;
    const double ny0 = 2 * y0 / height - 1, ny1 = 2 * y1 / height - 1;
    Frustum f;
    f.planes[0] = plane_from(combine(rx, -nx0, rw));
    f.planes[1] = plane_from(combine(combine(Row{0, 0, 0, 0}, nx1, rw), -1, rx));
    f.planes[2] = plane_from(combine(ry, -ny0, rw));
    f.planes[3] = plane_from(combine(combine(Row{0, 0, 0, 0}, ny1, rw), -1, ry));
    f.planes[4] = plane_from(combine(rz, 1, rw));
    f.planes[5] = plane_from(combine(rw, -1, rz));
    return f;
}

bool Frustum::touches_segment(const Vec3& a, const Vec3& b, double u0, double u1, double radius) const {
    return first_touch(a, b, u0, u1, radius) >= 0;
}

double Frustum::first_touch(const Vec3& a, const Vec3& b, double u0, double u1, double radius) const {
    // Liang-Barsky clipping of the parameter interval against each half-space.
    for (const Plane& plane : planes) {
        const double da = plane.distance(a) + radius;
        const double db = plane.distance(b) + radius;
        if (da < 0 && db < 0) return -1;
        if (da < 0) u0 = std::max(u0, da / (da - db));
        else if (db < 0) u1 = std::min(u1, da / (da - db));
        if (u0 > u1) return -1;
    }
    return u0;
}

double Frustum::view_relative_distance(const Vec3& p, double radius) const {
    double farthest = 0;
    for (size_t k = 0; k < planes.size(); k += 2) {
        const double d0 = planes[k].distance(p) + radius, d1 = planes[k + 1].distance(p) + radius;
        // d0 + d1 is the box's extent between the two planes where p is (exact for parallel
        // planes, the local width for a perspective box's sides).
        const double width = std::max(d0 + d1 - 2 * radius, 1e-9);
        farthest = std::max({farthest, -d0 / width, -d1 / width});
    }
    return farthest;
}

int Frustum::classify_box(const Vec3& center, const std::array<Vec3, 3>& axes, const Vec3& half_extents,
                          double radius, unsigned* crossing, unsigned tested) const {
    unsigned not_inside = 0;
    for (unsigned rest = tested & 0x3fu; rest != 0; rest &= rest - 1) {
        const auto i = static_cast<size_t>(__builtin_ctz(rest));
        const Plane& plane = planes[i];
        const double reach = std::fabs(dot(plane.normal, axes[0])) * half_extents[0] +
                             std::fabs(dot(plane.normal, axes[1])) * half_extents[1] +
                             std::fabs(dot(plane.normal, axes[2])) * half_extents[2] + radius;
        const double s = plane.distance(center);
        if (s < -reach) return -1;
        if (s < reach) not_inside |= 1u << i;
    }
    if (crossing) *crossing = not_inside;
    return not_inside == 0 ? 1 : 0;
}

}  // namespace mwb
