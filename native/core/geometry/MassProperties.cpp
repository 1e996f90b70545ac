#include "geometry/MassProperties.h"

#include <algorithm>
#include <string>
#include <unordered_map>

#include "geometry/ConvexHull.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Matrix3 = std::array<double, 9>;

MassProperties diagonal(double volume_m3, const Vec3& center, double ixx, double iyy, double izz) {
    MassProperties out;
    out.volume_m3 = volume_m3;
    out.center_of_mass_m = center;
    out.inertia = {ixx, 0, 0, 0, iyy, 0, 0, 0, izz};
    return out;
}

void require_positive(double value, const char* what) {
    if (!(value > 0) || !std::isfinite(value))
        throw GeometryError(std::string(what) + " must be a positive finite size, got " + std::to_string(value));
}

MassProperties box(Vec3 h, double m) {
    // A flat BOX (Blender's BOX on a plane) collides as a thin plate; its mass is spread the same way.
    for (double& extent : h) extent = std::max(extent, kFlatShapeHalfThickness_m);
    return diagonal(8 * h[0] * h[1] * h[2], {0, 0, 0}, m * (h[1] * h[1] + h[2] * h[2]) / 3,
                    m * (h[0] * h[0] + h[2] * h[2]) / 3, m * (h[0] * h[0] + h[1] * h[1]) / 3);
}

MassProperties sphere(double r, double m) {
    require_positive(r, "sphere radius");
    const double i = 0.4 * m * r * r;
    return diagonal(4.0 / 3.0 * kPi * r * r * r, {0, 0, 0}, i, i, i);
}

MassProperties cylinder(double r, double h, double m) {
    require_positive(r, "cylinder radius");
    require_positive(h, "cylinder height");
    const double side = m * (3 * r * r + h * h) / 12;
    return diagonal(kPi * r * r * h, {0, 0, 0}, side, side, m * r * r / 2);
}

// A cylinder of length L = height - 2r with a hemisphere on each end.
MassProperties capsule(double r, double height, double m) {
    require_positive(r, "capsule radius");
    const double length = height - 2 * r;
    if (!(length >= 0))
        throw GeometryError("capsule height " + std::to_string(height) + " is less than twice its radius " +
                            std::to_string(r));
    const double cylinder_volume = kPi * r * r * length;
    const double caps_volume = 4.0 / 3.0 * kPi * r * r * r;
    const double volume = cylinder_volume + caps_volume;
    const double mc = m * cylinder_volume / volume, mh = m * caps_volume / volume;
    const double axial = mc * r * r / 2 + mh * 0.4 * r * r;
    // Each hemisphere's inertia about the capsule centre: its own (2/5 r² about the flat face),
    // shifted from the face to the centre by the parallel-axis theorem via its centroid at 3r/8.
    const double side = mc * (r * r / 4 + length * length / 12) +
                        mh * (0.4 * r * r + length * length / 4 + 3 * length * r / 8);
    return diagonal(volume, {0, 0, 0}, side, side, axial);
}

// Base disc at z = -h/2, apex at z = +h/2, so the centre of mass sits at z = -h/4.
MassProperties cone(double r, double h, double m) {
    require_positive(r, "cone radius");
    require_positive(h, "cone height");
    const double side = m * (3 * r * r / 20 + 3 * h * h / 80);
    return diagonal(kPi * r * r * h / 3, {0, 0, -h / 4}, side, side, 0.3 * m * r * r);
}

// ∫1, ∫x and ∫x xᵀ over a solid bounded by triangles, accumulated as signed tetrahedra from 0.
struct VolumeIntegrals {
    double volume = 0;
    Vec3 first{0, 0, 0};
    Matrix3 second{};

    void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
        const double det = dot(a, cross(b, c));
        const Vec3 s = add(add(a, b), c);
        volume += det / 6;
        first = add(first, scale(s, det / 24));
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                second[3 * i + j] += det / 120 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }

    // Mass properties for `mass_kg`, with the integrals taken about `origin`.
    MassProperties finish(const Vec3& origin, double mass_kg) const {
        if (!(volume > 0)) throw GeometryError("closed surface encloses no volume");
        const Vec3 com = scale(first, 1 / volume);
        Matrix3 central = second;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) central[3 * i + j] -= volume * com[i] * com[j];
        const double trace = central[0] + central[4] + central[8];
        MassProperties out;
        out.volume_m3 = volume;
        out.center_of_mass_m = add(origin, com);
        for (int k = 0; k < 9; ++k) out.inertia[k] = mass_kg / volume * ((k % 4 == 0 ? trace : 0) - central[k]);
        return out;
    }
};

Vec3 point(const std::vector<double>& xyz, uint32_t i) { return {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; }

// Centre of the bounding box: integrating about it keeps the products of coordinates small.
Vec3 reference_point(const std::vector<Vec3>& points) {
    Vec3 lo = points.front(), hi = points.front();
    for (const Vec3& p : points)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    return scale(add(lo, hi), 0.5);
}

MassProperties convex_hull(const std::vector<double>& xyz, double m) {
    const ConvexHull hull = compute_convex_hull(thicken_flat_points(xyz));
    const Vec3 origin = reference_point(hull.points);
    VolumeIntegrals integrals;
    for (const auto& face : hull.faces) {
        const Vec3 first = sub(hull.points[face[0]], origin);
        for (size_t i = 1; i + 1 < face.size(); ++i)
            integrals.add_triangle(first, sub(hull.points[face[i]], origin), sub(hull.points[face[i + 1]], origin));
    }
    return integrals.finish(origin, m);
}

// Closed: every directed edge appears once and its reverse appears too (consistently wound).
bool is_closed(const std::vector<uint32_t>& triangles) {
    std::unordered_map<uint64_t, int> directed;
    for (size_t t = 0; t < triangles.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            const uint64_t key = (static_cast<uint64_t>(triangles[t + k]) << 32) | triangles[t + (k + 1) % 3];
            if (++directed[key] > 1) return false;
        }
    }
    for (const auto& [key, count] : directed)
        if (!directed.count((key << 32) | (key >> 32))) return false;
    return true;
}

MassProperties mesh(const Shape& shape, double m) {
    const std::vector<double>& xyz = shape.vertices_m;
    const size_t vertex_count = xyz.size() / 3;
    if (xyz.size() % 3 != 0 || shape.triangles.size() % 3 != 0 || shape.triangles.empty())
        throw GeometryError("mesh needs (n, 3) vertices and a non-empty (m, 3) triangle list");
    for (uint32_t index : shape.triangles)
        if (index >= vertex_count) throw GeometryError("mesh triangle index " + std::to_string(index) + " is out of range");
    if (!is_closed(shape.triangles)) return convex_hull(xyz, m);

    std::vector<Vec3> points(vertex_count);
    for (uint32_t i = 0; i < vertex_count; ++i) points[i] = point(xyz, i);
    const Vec3 origin = reference_point(points);
    VolumeIntegrals integrals;
    const auto& tri = shape.triangles;
    for (size_t t = 0; t < tri.size(); t += 3)
        integrals.add_triangle(sub(points[tri[t]], origin), sub(points[tri[t + 1]], origin), sub(points[tri[t + 2]], origin));
    // A closed mesh wound inside-out is still a solid: flip it.
    if (integrals.volume < 0) {
        integrals.volume = -integrals.volume;
        integrals.first = scale(integrals.first, -1);
        for (double& v : integrals.second) v = -v;
    }
    return integrals.finish(origin, m);
}

Matrix3 rotation_matrix(const Quat& q) {
    Matrix3 r{};
    for (int column = 0; column < 3; ++column) {
        Vec3 axis{0, 0, 0};
        axis[column] = 1;
        const Vec3 image = quat_rotate(q, axis);
        for (int row = 0; row < 3; ++row) r[3 * row + column] = image[row];
    }
    return r;
}

// R I Rᵀ: an inertia tensor expressed in the parent frame.
Matrix3 rotate_tensor(const Matrix3& r, const Matrix3& inertia) {
    Matrix3 out{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l) out[3 * i + j] += r[3 * i + k] * inertia[3 * k + l] * r[3 * j + l];
    return out;
}

MassProperties compound(const Shape& shape, double m) {
    if (shape.children.empty()) throw GeometryError("compound shape has no children");
    std::vector<MassProperties> parts;
    double volume = 0;
    for (const Shape& child : shape.children) {
        MassProperties unit = compute_mass_properties(child, 1.0);
        unit.center_of_mass_m = add(child.offset.location, quat_rotate(child.offset.rotation, unit.center_of_mass_m));
        unit.inertia = rotate_tensor(rotation_matrix(child.offset.rotation), unit.inertia);
        volume += unit.volume_m3;
        parts.push_back(unit);
    }
    Vec3 com{0, 0, 0};
    for (const MassProperties& part : parts) com = add(com, scale(part.center_of_mass_m, part.volume_m3 / volume));
    MassProperties out;
    out.volume_m3 = volume;
    out.center_of_mass_m = com;
    for (const MassProperties& part : parts) {
        // Mass is split by volume (uniform density); then the parallel-axis theorem moves each
        // child's inertia from its own centre of mass to the compound's.
        const double mi = m * part.volume_m3 / volume;
        const Vec3 d = sub(part.center_of_mass_m, com);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                out.inertia[3 * i + j] += mi * (part.inertia[3 * i + j] + ((i == j ? dot(d, d) : 0) - d[i] * d[j]));
    }
    return out;
}

}  // namespace

MassProperties compute_mass_properties(const Shape& shape, double mass_kg) {
    switch (shape.type) {
        case ShapeType::Box: return box(shape.half_extents_m, mass_kg);
        case ShapeType::Sphere: return sphere(shape.radius_m, mass_kg);
        case ShapeType::Capsule: return capsule(shape.radius_m, shape.height_m, mass_kg);
        case ShapeType::Cylinder: return cylinder(shape.radius_m, shape.height_m, mass_kg);
        case ShapeType::Cone: return cone(shape.radius_m, shape.height_m, mass_kg);
        case ShapeType::ConvexHull: return convex_hull(shape.vertices_m, mass_kg);
        case ShapeType::Mesh: return mesh(shape, mass_kg);
        case ShapeType::Compound: return compound(shape, mass_kg);
    }
    throw GeometryError("unknown shape type");
}

}  // namespace mwb
