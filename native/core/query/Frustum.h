#pragma once
// A screen-space query box as a frustum in world space, and exact tests of path segments,
// spheres and oriented boxes against it.
#include <array>

#include "common/Math.h"

namespace mwb {

/// Row-major 4x4 matrix acting on column vectors (Blender's Matrix @ vector convention).
using Matrix4 = std::array<double, 16>;

/// Inside where normal·x + offset >= 0.
struct Plane {
    Vec3 normal{0, 0, 1};
    double offset = 0;
    double distance(const Vec3& p) const { return dot(normal, p) + offset; }
};

struct Frustum {
    std::array<Plane, 6> planes;  ///< left, right, bottom, top, near, far; unit normals

    /// Whether the segment a→b (parameter u in [u0, u1] ⊆ [0, 1]) has a point within `radius`
    /// of the inside: exact for radius 0 (the segment is clipped against every plane); for
    /// radius > 0 the planes move out by radius, which is exact across faces and conservative
    /// near edges and corners.
    bool touches_segment(const Vec3& a, const Vec3& b, double u0, double u1, double radius = 0) const;
    /// The smallest u in [u0, u1] where the segment a→b touches (as touches_segment decides), or a
    /// negative value if it does not.
    double first_touch(const Vec3& a, const Vec3& b, double u0, double u1, double radius = 0) const;
    /// How far `p` (grown by `radius`) is outside, in units of the box's own size where p is: for
    /// each pair of opposite planes (left/right, bottom/top, near/far), the distance beyond one of
    /// them divided by the distance between them; the largest of the three. 0 inside. Screen boxes
    /// are drawn at any zoom, so closeness in box sizes means the same in every view.
    double view_relative_distance(const Vec3& p, double radius = 0) const;
    /// Classifies a box (centre, unit axes, half extents) grown by `radius` against the planes in
    /// `tested` (bit i: planes[i]): -1 entirely outside one, +1 entirely inside all, 0 otherwise
    /// (possibly crossing). With 0, `crossing` (if given) gets a bit per tested plane the box is
    /// not wholly inside.
    int classify_box(const Vec3& center, const std::array<Vec3, 3>& axes, const Vec3& half_extents, double radius,
                     unsigned* crossing = nullptr, unsigned tested = 0x3f) const;
};

/// The frustum of the screen rectangle [x0, x1] × [y0, y1] (pixels, origin at the bottom-left of
/// a viewport of width × height pixels) seen through `view` (world to camera) and `projection`
/// (camera to clip, OpenGL convention: perspective or orthographic). Throws std::invalid_argument
/// for an empty rectangle or a singular camera.
Frustum make_screen_frustum(const Matrix4& view, const Matrix4& projection, double width, double height, double x0,
                            double y0, double x1, double y1);

Matrix4 multiply(const Matrix4& a, const Matrix4& b);

}  // namespace mwb
