#include "sim/CompiledScene.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/PortableMath.h"
#include "geometry/ConvexHull.h"
#include "geometry/MassProperties.h"
#include "scene/SceneJson.h"
#include "scene/SceneValidation.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kConeSegments = 24;
// Ghosts replay stored motion; a centimetre more catches contacts the 1 mm codec error or the
// 30 Hz replay could miss.
constexpr double kGhostMargin_m = 0.01;
// A flat BOX (Blender's BOX on a plane) collides as a plate kFlatShapeHalfThickness_m thick each
// side; a static one lying within 30° of level is thickened below its top face instead, so that
// fast bodies cannot cross its mid-plane while the face they land on stays where Blender has it.
constexpr double kGroundPlateThickness_m = 0.02;
constexpr double kGroundPlateMaxTiltCos = 0.866;
// A convex geom's origin must be at least this fraction of its reach inside each face, so that
// ODE's check of each face (the sign of a determinant) cannot be tipped by rounding.
constexpr double kConvexOriginClearance = 1e-6;

Transform compose(const Transform& parent, const Transform& child) {
    return {add(parent.location, quat_rotate(parent.rotation, child.location)),
            quat_normalized(quat_multiply(parent.rotation, child.rotation))};
}

// Flat (n, 3) points of `shape` placed by `placement` and shifted so `frame_origin` becomes 0.
std::vector<double> place_points(const std::vector<double>& xyz, const Transform& placement,
                                 const Vec3& frame_origin) {
    std::vector<double> out(xyz.size());
    for (size_t i = 0; i + 2 < xyz.size(); i += 3) {
        const Vec3 p = sub(add(placement.location, quat_rotate(placement.rotation, {xyz[i], xyz[i + 1], xyz[i + 2]})),
                           frame_origin);
        out[i] = p[0];
        out[i + 1] = p[1];
        out[i + 2] = p[2];
    }
    return out;
}

std::vector<double> cone_points(double radius, double height) {
    std::vector<double> points{0, 0, height / 2};
    for (int i = 0; i < kConeSegments; ++i) {
        const double a = 2 * kPi * i / kConeSegments;
        points.insert(points.end(), {radius * portable::cos(a), radius * portable::sin(a), -height / 2});
    }
    return points;
}

// Bullet's collision margin around a convex shape (its Minkowski sum with a sphere): every face
// of the hull moves out by `margin`; edges and corners are bevelled instead of rounded.
void grow_hull_points(std::vector<double>& xyz, double margin) {
    const ConvexHull hull = compute_convex_hull(xyz);
    xyz.clear();
    for (size_t f = 0; f < hull.faces.size(); ++f) {
        const Vec3 outward = scale({hull.planes[f][0], hull.planes[f][1], hull.planes[f][2]}, margin);
        for (uint32_t i : hull.faces[f]) {
            const Vec3 p = add(hull.points[i], outward);
            xyz.insert(xyz.end(), p.begin(), p.end());
        }
    }
}

// Bullet thickens every triangle of a MESH shape by its collision margin. ODE's triangle meshes
// have none, so each vertex moves out along its normal by as much as keeps every adjacent face
// `margin` further out (exact on flat and convex regions, capped at sharp edges).
void thicken_mesh(std::vector<double>& xyz, const std::vector<uint32_t>& triangles, double margin) {
    const size_t n = xyz.size() / 3;
    auto vertex = [&](uint32_t i) { return Vec3{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; };
    std::vector<Vec3> normals(n, Vec3{0, 0, 0}), faces;
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const Vec3 a = vertex(triangles[t]), b = vertex(triangles[t + 1]), c = vertex(triangles[t + 2]);
        const Vec3 area = cross(sub(b, a), sub(c, a));  // twice the area, along the face normal
        faces.push_back(area);
        for (int k = 0; k < 3; ++k) normals[triangles[t + k]] = add(normals[triangles[t + k]], area);
    }
    std::vector<double> least_cos(n, 1.0);
    for (Vec3& v : normals) {
        const double len = norm(v);
        v = len > 0 ? scale(v, 1 / len) : Vec3{0, 0, 0};
    }
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const double len = norm(faces[t / 3]);
        if (len <= 0) continue;
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = triangles[t + k];
            least_cos[i] = std::min(least_cos[i], dot(normals[i], scale(faces[t / 3], 1 / len)));
        }
    }
    for (size_t i = 0; i < n; ++i) {
        const double reach = margin / std::max(least_cos[i], 1.0 / 3.0);
        for (int k = 0; k < 3; ++k) xyz[3 * i + k] += normals[i][k] * reach;
    }
}

// A hull that is a box (eight corners, six rectangular faces: a cube with Blender's default
// CONVEX_HULL shape) as a box part: ODE's box contacts keep a stack of them still, where its
// general convex contacts let it creep apart. False for any other hull.
bool box_of_hull(const ConvexHull& hull, CollisionPart& part) {
    if (hull.points.size() != 8 || hull.faces.size() != 6) return false;
    std::vector<Vec3> axes;
    for (const auto& plane : hull.planes) {
        const Vec3 n{plane[0], plane[1], plane[2]};
        if (std::none_of(axes.begin(), axes.end(), [&](const Vec3& a) { return std::fabs(dot(a, n)) > 1 - 1e-9; }))
            axes.push_back(n);
    }
    if (axes.size() != 3) return false;
    for (int i = 0; i < 3; ++i)
        if (std::fabs(dot(axes[i], axes[(i + 1) % 3])) > 1e-9) return false;
    axes[2] = cross(axes[0], axes[1]);
    Vec3 center{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        double lo = 1e300, hi = -1e300;
        for (const Vec3& p : hull.points) lo = std::min(lo, dot(p, axes[a])), hi = std::max(hi, dot(p, axes[a]));
        part.half_extents_m[a] = (hi - lo) / 2;
        center = add(center, scale(axes[a], (hi + lo) / 2));
    }
    part.kind = PartKind::Box;
    part.offset = {center, quat_from_axes(axes[0], axes[1], axes[2])};
    return true;
}

// Where ODE's convex geom of `hull` (body frame) has its origin: ODE requires the origin inside
// every face. The body frame's own origin when it is well inside (a simulated body's centre of
// mass), else the mean of the hull's corners (a passive hull whose object origin lies on or off
// its surface, a compound's part).
Vec3 convex_geom_origin(const ConvexHull& hull) {
    double extent = 0;
    for (const Vec3& p : hull.points) extent = std::max(extent, norm(p));
    double nearest_face = extent;
    for (const auto& plane : hull.planes) nearest_face = std::min(nearest_face, plane[3]);
    if (nearest_face > kConvexOriginClearance * extent) return {0, 0, 0};
    Vec3 mean{0, 0, 0};
    for (const Vec3& p : hull.points) mean = add(mean, p);
    return scale(mean, 1.0 / static_cast<double>(hull.points.size()));
}

// The part of a convex shape of `points` (body frame) grown by `margin`: a box when the hull is a
// box (its faces moved out), else a general convex hull (faces moved out, edges bevelled).
CollisionPart convex_part(std::vector<double> points, double margin) {
    CollisionPart part;
    if (box_of_hull(compute_convex_hull(points), part)) {
        for (double& extent : part.half_extents_m) extent += margin;
        return part;
    }
    if (margin > 0) grow_hull_points(points, margin);
    const ConvexHull hull = compute_convex_hull(points);
    part.kind = PartKind::Convex;
    part.offset.location = convex_geom_origin(hull);
    const Vec3& origin = part.offset.location;
    for (const Vec3& p : hull.points) {
        const Vec3 q = sub(p, origin);
        part.convex_points.insert(part.convex_points.end(), q.begin(), q.end());
    }
    for (const auto& plane : hull.planes)
        part.convex_planes.insert(part.convex_planes.end(),
                                  {plane[0], plane[1], plane[2], plane[3] - dot({plane[0], plane[1], plane[2]}, origin)});
    for (const auto& face : hull.faces) {
        part.convex_polygons.push_back(static_cast<unsigned int>(face.size()));
        part.convex_polygons.insert(part.convex_polygons.end(), face.begin(), face.end());
    }
    part.convex_point_count = static_cast<unsigned int>(hull.points.size());
    part.convex_plane_count = static_cast<unsigned int>(hull.planes.size());
    return part;
}

double part_bounding_radius(const CollisionPart& part) {
    const double center = norm(part.offset.location);
    switch (part.kind) {
        case PartKind::Box: return center + norm(part.half_extents_m);
        case PartKind::Sphere: return center + part.radius_m;
        case PartKind::Capsule: return center + part.radius_m + part.length_m / 2;
        case PartKind::Cylinder: return center + portable::hypot(part.radius_m, part.length_m / 2);
        case PartKind::Convex:
        case PartKind::TriangleMesh: {
            // Convex points are about the part's offset (identity rotation); mesh points are not.
            const auto& xyz = part.kind == PartKind::Convex ? part.convex_points : part.mesh_vertices;
            const Vec3 shift = part.kind == PartKind::Convex ? part.offset.location : Vec3{0, 0, 0};
            double r = 0;
            for (size_t i = 0; i + 2 < xyz.size(); i += 3)
                r = std::max(r, norm(add(shift, {xyz[i], xyz[i + 1], xyz[i + 2]})));
            return r;
        }
    }
    return center;
}

// Margins as Blender gives them to Bullet: `hull` grows convex hulls, `outer` grows cones and
// triangle meshes; inside boxes, spheres, capsules and cylinders the margin changes nothing.
struct Margins {
    double hull = 0;
    double outer = 0;
};

// Appends the collision parts of `shape` (placed by `placement` in the object frame) to `parts`, in
// the body frame whose origin is `origin` in the object frame; `grow` enlarges every part.
void compile_shape(const Shape& shape, const Transform& placement, const Margins& margins, double grow,
                   const Vec3& origin, std::vector<CollisionPart>& parts, bool& has_mesh) {
    const double margin = grow;
    CollisionPart part;
    part.offset = {sub(placement.location, origin), placement.rotation};
    switch (shape.type) {
        case ShapeType::Box:
            part.kind = PartKind::Box;
            for (int k = 0; k < 3; ++k) part.half_extents_m[k] = std::max(shape.half_extents_m[k], kFlatShapeHalfThickness_m) + margin;
            break;
        case ShapeType::Sphere:
            part.kind = PartKind::Sphere;
            part.radius_m = shape.radius_m + margin;
            break;
        case ShapeType::Capsule:
            part.kind = PartKind::Capsule;
            part.radius_m = shape.radius_m + margin;
            part.length_m = std::max(0.0, shape.height_m - 2 * shape.radius_m);
            break;
        case ShapeType::Cylinder:
            part.kind = PartKind::Cylinder;
            part.radius_m = shape.radius_m + margin;
            part.length_m = shape.height_m + 2 * margin;
            break;
        case ShapeType::Cone:
        case ShapeType::ConvexHull: {
            std::vector<double> local = shape.type == ShapeType::Cone ? cone_points(shape.radius_m, shape.height_m)
                                                                      : thicken_flat_points(shape.vertices_m);
            const double outward = grow + (shape.type == ShapeType::ConvexHull ? margins.hull : margins.outer);
            part = convex_part(place_points(local, placement, origin), outward);
            break;
        }
        case ShapeType::Mesh:
            // A mesh that is the whole surface of a convex shape (a box, a ground plane) collides as
            // that shape grown by the margin, as Bullet's thickened triangles do: ODE's convex-vs-mesh
            // contacts let convex bodies sink through large triangles.
            if (mesh_fills_its_hull(shape.vertices_m, shape.triangles)) {
                part = convex_part(place_points(thicken_flat_points(shape.vertices_m), placement, origin),
                                   margins.outer + grow);
                part.mesh_margin_m = margins.outer;
                break;
            }
            part.kind = PartKind::TriangleMesh;
            part.mesh_vertices = shape.vertices_m;
            if (margins.outer + grow > 0) thicken_mesh(part.mesh_vertices, shape.triangles, margins.outer + grow);
            part.mesh_margin_m = margins.outer;
            part.mesh_vertices = place_points(part.mesh_vertices, placement, origin);
            part.mesh_indices = shape.triangles;
            has_mesh = true;
            break;
        case ShapeType::Compound:
            for (const Shape& child : shape.children)
                compile_shape(child, compose(placement, child.offset), margins, grow, origin, parts, has_mesh);
            return;
    }
    parts.push_back(std::move(part));
}

// A static BOX whose shape is flat along an axis within 30° of up: its plate grows below the top
// face (see kGroundPlateThickness_m).
void thicken_ground_plate(const Body& body, const Vec3& gravity, std::vector<CollisionPart>& parts) {
    const double g = norm(gravity);
    if (body.shape.type != ShapeType::Box || parts.size() != 1 || g <= 0) return;
    for (int axis = 0; axis < 3; ++axis) {
        if (body.shape.half_extents_m[axis] >= kFlatShapeHalfThickness_m) continue;
        Vec3 local{0, 0, 0};
        local[axis] = 1;
        const double up = -dot(quat_rotate(body.initial.rotation, local), gravity) / g;
        if (std::fabs(up) < kGroundPlateMaxTiltCos) continue;
        const double grown = kGroundPlateThickness_m / 2 - kFlatShapeHalfThickness_m;
        parts[0].half_extents_m[axis] += grown;
        parts[0].offset.location[axis] -= (up > 0 ? 1 : -1) * (grown + kFlatShapeHalfThickness_m);
        return;
    }
}

CompiledBody compile_body(const Body& body, const Vec3& gravity) {
    CompiledBody out;
    out.kinematic = body_role(body) == BodyRole::Animated;
    out.dynamic = body_role(body) == BodyRole::Simulated;
    if (out.dynamic) {
        const MassProperties mass = compute_mass_properties(body.shape, body.mass_kg);
        out.body_frame_offset_m = body.has_center_of_mass ? body.center_of_mass_local_m : mass.center_of_mass_m;
        out.inertia = mass.inertia;
    }
    // As in Blender: hulls grow by the margin only when "Collision Margin" is set (otherwise Bullet
    // shrinks them by 0.04 and adds it back); cones and meshes always grow by it.
    const Margins margins{body.use_margin ? body.collision_margin_m : 0.0, body.collision_margin_m};
    compile_shape(body.shape, Transform{}, margins, 0.0, out.body_frame_offset_m, out.parts, out.has_mesh);
    bool ghost_mesh = false;
    compile_shape(body.shape, Transform{}, margins, kGhostMargin_m, out.body_frame_offset_m, out.ghost_parts, ghost_mesh);
    if (!out.dynamic && !out.kinematic) {
        thicken_ground_plate(body, gravity, out.parts);
        thicken_ground_plate(body, gravity, out.ghost_parts);
    }
    for (const CollisionPart& part : out.parts)
        out.bounding_radius_m = std::max(out.bounding_radius_m, part_bounding_radius(part));
    return out;
}

std::vector<std::string> validate_parameters(const SimulationParameters& p) {
    std::vector<std::string> problems;
    auto require = [&](bool ok, const char* field, const char* rule) {
        if (!ok) problems.push_back(std::string("parameters.") + field + ": " + rule);
    };
    require(std::isfinite(p.duration_s), "duration_s", "must be finite");
    require(p.min_step_hz > 0 && std::isfinite(p.min_step_hz), "min_step_hz", "must be > 0");
    require(p.record_hz > 0 && std::isfinite(p.record_hz), "record_hz", "must be > 0");
    require(p.alpha_linear >= 0 && p.alpha_linear <= 1, "alpha_linear", "must be in [0, 1]");
    require(p.alpha_angular >= 0 && p.alpha_angular <= 1, "alpha_angular", "must be in [0, 1]");
    require(p.lobe_exponent >= 0 && std::isfinite(p.lobe_exponent), "lobe_exponent", "must be >= 0");
    require(p.impact_linear_factor > 0, "impact_linear_factor", "must be > 0");
    require(p.impact_angular_factor > 0, "impact_angular_factor", "must be > 0");
    require(p.rest_duration_s >= 0, "rest_duration_s", "must be >= 0");
    require(p.checkpoint_interval_s > 0, "checkpoint_interval_s", "must be > 0");
    require(p.max_speed_mps > 0 && p.max_distance_m > 0, "max_speed_mps/max_distance_m", "must be > 0");
    return problems;
}

}  // namespace

CompiledScene::CompiledScene(Scene scene, const SimulationParameters& parameters, size_t sampled_body_count)
    : scene_(std::move(scene)), parameters_(parameters) {
    sampled_body_count_ = std::min(sampled_body_count, scene_.bodies.size());
    std::vector<std::string> problems = validate_scene(scene_);
    for (std::string& p : validate_parameters(parameters_)) problems.push_back(std::move(p));
    if (!problems.empty()) {
        std::ostringstream message;
        for (size_t i = 0; i < problems.size(); ++i) message << (i ? "\n" : "") << problems[i];
        throw SceneError(message.str());
    }
    for (const Body& body : scene_.bodies) {
        try {
            bodies_.push_back(compile_body(body, scene_.world.gravity));
        } catch (const GeometryError& error) {
            throw SceneError("body '" + body.name + "'.shape: " + error.what());
        }
    }
    const WorldSettings& world = scene_.world;
    const double wanted_hz = std::max(parameters_.min_step_hz, world.fps * world.substeps_per_frame);
    steps_per_frame_ = static_cast<uint32_t>(std::max(1.0, std::ceil(wanted_hz / parameters_.record_hz - 1e-9)));
    step_hz_ = parameters_.record_hz * steps_per_frame_;
    for (size_t i = 0; i < bodies_.size(); ++i)
        if (bodies_[i].dynamic && scene_.bodies[i].animated_until_s > 0)
            bodies_[i].handoff_step = static_cast<uint64_t>(std::ceil(scene_.bodies[i].animated_until_s * step_hz_ - 1e-9));
    duration_s_ = run_duration_s(parameters_, world);
    total_steps_ = run_last_frame(parameters_, world) * steps_per_frame_;
    steps_per_checkpoint_ = std::max<uint64_t>(
        steps_per_frame_,
        static_cast<uint64_t>(std::llround(parameters_.checkpoint_interval_s * parameters_.record_hz)) * steps_per_frame_);
}

}  // namespace mwb
