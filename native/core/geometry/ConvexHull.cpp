#include "geometry/ConvexHull.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

namespace mwb {
namespace {

// Distances within this fraction of the cloud's half-diagonal count as zero (coplanar, duplicate
// or interior): far above double rounding, far below any modelling detail.
constexpr double kRelativeTolerance = 1e-9;
// A face's first corner narrower than this fraction of its widest one is not trusted to ODE.
constexpr double kNarrowCornerFraction = 1e-3;

// The hull folded over at this tolerance (rounding, near-duplicate points): a coarser one may not.
struct FoldedHull : GeometryError {
    using GeometryError::GeometryError;
};

struct Triangle {
    std::array<uint32_t, 3> v;
    Vec3 normal;
    double offset;                  // normal·x = offset
    std::vector<uint32_t> outside;  // points above this face by more than the tolerance
    bool alive = true;
};

uint64_t edge_key(uint32_t from, uint32_t to) { return (static_cast<uint64_t>(from) << 32) | to; }

std::vector<Vec3> read_points(const std::vector<double>& xyz) {
    if (xyz.size() % 3 != 0)
        throw GeometryError("convex hull: " + std::to_string(xyz.size()) +
                            " coordinates is not a multiple of 3");
    std::vector<Vec3> points(xyz.size() / 3);
    for (size_t i = 0; i < points.size(); ++i) {
        points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        if (!std::isfinite(points[i][0]) || !std::isfinite(points[i][1]) || !std::isfinite(points[i][2]))
            throw GeometryError("convex hull: point " + std::to_string(i) + " is not finite");
    }
    if (points.size() < 4)
        throw GeometryError("convex hull needs at least 4 points, got " + std::to_string(points.size()));
    return points;
}

Vec3 bounds_center(const std::vector<Vec3>& points, double& half_diagonal) {
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], p[k]);
            hi[k] = std::max(hi[k], p[k]);
        }
    }
    half_diagonal = norm(sub(hi, lo)) / 2;
    return scale(add(lo, hi), 0.5);
}

// Newell's normal of a closed polygon: robust for many vertices and nearly collinear runs.
Vec3 newell_normal(const std::vector<Vec3>& points, const std::vector<uint32_t>& loop) {
    Vec3 n{0, 0, 0};
    for (size_t i = 0; i < loop.size(); ++i) {
        const Vec3& a = points[loop[i]];
        const Vec3& b = points[loop[(i + 1) % loop.size()]];
        n = add(n, {(a[1] - b[1]) * (a[2] + b[2]), (a[2] - b[2]) * (a[0] + b[0]), (a[0] - b[0]) * (a[1] + b[1])});
    }
    return n;
}

// Incremental quickhull over points centred on their bounding box (so precision follows the
// extent, not the distance from the origin), followed by merging coplanar triangles.
class HullBuilder {
public:
    HullBuilder(std::vector<Vec3> points, double tolerance) : points_(std::move(points)), tol_(tolerance) {}

    void build() {
        add_initial_tetrahedron();
        while (!pending_.empty()) {
            const uint32_t face = pending_.back();
            pending_.pop_back();
            if (faces_[face].alive && !faces_[face].outside.empty()) add_farthest_point_of(face);
        }
    }

    /// Coplanar triangles merged into convex polygons, as loops of point indices.
    std::vector<std::vector<uint32_t>> polygons() const;

    const std::vector<Vec3>& points() const { return points_; }

private:
    double distance(uint32_t face, uint32_t point) const {
        return dot(faces_[face].normal, points_[point]) - faces_[face].offset;
    }

    uint32_t find_face(uint32_t from, uint32_t to) const {
        auto it = edges_.find(edge_key(from, to));
        if (it == edges_.end()) throw FoldedHull("convex hull: numerical breakdown (open edge)");
        return it->second;
    }

    uint32_t add_face(uint32_t a, uint32_t b, uint32_t c) {
        Triangle t;
        t.v = {a, b, c};
        const Vec3 n = cross(sub(points_[b], points_[a]), sub(points_[c], points_[a]));
        t.normal = scale(n, 1.0 / norm(n));
        t.offset = (dot(t.normal, points_[a]) + dot(t.normal, points_[b]) + dot(t.normal, points_[c])) / 3;
        const auto index = static_cast<uint32_t>(faces_.size());
        for (int k = 0; k < 3; ++k) {
            // A directed edge already in use means the surface folded over: give up cleanly.
            if (!edges_.emplace(edge_key(t.v[k], t.v[(k + 1) % 3]), index).second)
                throw FoldedHull("convex hull: numerical breakdown (repeated edge)");
        }
        faces_.push_back(std::move(t));
        return index;
    }

    void remove_face(uint32_t face) {
        Triangle& t = faces_[face];
        for (int k = 0; k < 3; ++k) edges_.erase(edge_key(t.v[k], t.v[(k + 1) % 3]));
        t.alive = false;
    }

    // Gives `point` to the first of `candidates` it lies above; points above none are inside.
    void assign(uint32_t point, const std::vector<uint32_t>& candidates) {
        for (uint32_t face : candidates) {
            if (distance(face, point) > tol_) {
                if (faces_[face].outside.empty()) pending_.push_back(face);
                faces_[face].outside.push_back(point);
                return;
            }
        }
    }

    void add_initial_tetrahedron();
    void add_farthest_point_of(uint32_t face);
    std::vector<uint32_t> visible_faces(uint32_t seed, uint32_t eye);

    std::vector<Vec3> points_;
    double tol_;
    std::vector<Triangle> faces_;
    std::unordered_map<uint64_t, uint32_t> edges_;  // directed edge -> face that owns it
    std::vector<uint32_t> pending_;                // faces that may have outside points
};

void HullBuilder::add_initial_tetrahedron() {
    const uint32_t n = static_cast<uint32_t>(points_.size());
    // The two farthest apart among the axis-extreme points span the first edge.
    std::array<uint32_t, 6> extremes{};
    for (uint32_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            if (points_[i][k] < points_[extremes[2 * k]][k]) extremes[2 * k] = i;
            if (points_[i][k] > points_[extremes[2 * k + 1]][k]) extremes[2 * k + 1] = i;
        }
    }
    uint32_t a = extremes[0], b = extremes[1];
    for (uint32_t i : extremes)
        for (uint32_t j : extremes)
            if (norm(sub(points_[i], points_[j])) > norm(sub(points_[a], points_[b]))) a = i, b = j;
    if (norm(sub(points_[a], points_[b])) <= tol_) throw GeometryError("convex hull: all points coincide");

    const Vec3 ab = sub(points_[b], points_[a]);
    uint32_t c = a;
    double best = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const double d = norm(cross(sub(points_[i], points_[a]), ab)) / norm(ab);
        if (d > best) best = d, c = i;
    }
    if (best <= tol_) throw GeometryError("convex hull: all points are collinear");

    const Vec3 normal = cross(ab, sub(points_[c], points_[a]));
    const Vec3 unit = scale(normal, 1.0 / norm(normal));
    uint32_t d = a;
    best = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const double dist = std::fabs(dot(unit, sub(points_[i], points_[a])));
        if (dist > best) best = dist, d = i;
    }
    if (best <= tol_) throw GeometryError("convex hull: all points are coplanar");

    // Wind (a, b, c) so that d lies behind it; the other three faces follow from that.
    if (dot(normal, sub(points_[d], points_[a])) > 0) std::swap(b, c);
    const std::vector<uint32_t> first{add_face(a, b, c), add_face(a, d, b), add_face(b, d, c), add_face(c, d, a)};
    for (uint32_t i = 0; i < n; ++i)
        if (i != a && i != b && i != c && i != d) assign(i, first);
}

std::vector<uint32_t> HullBuilder::visible_faces(uint32_t seed, uint32_t eye) {
    // Grow from the seed across edges so the visible region stays connected.
    std::vector<uint32_t> visible{seed};
    std::vector<uint32_t> stack{seed};
    std::vector<bool> seen(faces_.size(), false);
    seen[seed] = true;
    while (!stack.empty()) {
        const Triangle& t = faces_[stack.back()];
        stack.pop_back();
        for (int k = 0; k < 3; ++k) {
            const uint32_t next = find_face(t.v[(k + 1) % 3], t.v[k]);
            if (seen[next]) continue;
            seen[next] = true;
            if (distance(next, eye) > tol_) {
                visible.push_back(next);
                stack.push_back(next);
            }
        }
    }
    return visible;
}

void HullBuilder::add_farthest_point_of(uint32_t face) {
    const std::vector<uint32_t>& candidates = faces_[face].outside;
    const uint32_t eye = *std::max_element(candidates.begin(), candidates.end(),
                                           [&](uint32_t p, uint32_t q) { return distance(face, p) < distance(face, q); });
    const std::vector<uint32_t> visible = visible_faces(face, eye);

    std::vector<bool> is_visible(faces_.size(), false);
    for (uint32_t f : visible) is_visible[f] = true;
    std::vector<std::pair<uint32_t, uint32_t>> horizon;
    std::vector<uint32_t> orphans;
    for (uint32_t f : visible) {
        const Triangle& t = faces_[f];
        for (int k = 0; k < 3; ++k)
            if (!is_visible[find_face(t.v[(k + 1) % 3], t.v[k])]) horizon.emplace_back(t.v[k], t.v[(k + 1) % 3]);
        for (uint32_t p : t.outside)
            if (p != eye) orphans.push_back(p);
    }
    for (uint32_t f : visible) {
        remove_face(f);
        faces_[f].outside.clear();
        faces_[f].outside.shrink_to_fit();
    }
    std::vector<uint32_t> cone;
    for (const auto& [from, to] : horizon) cone.push_back(add_face(from, to, eye));
    for (uint32_t p : orphans) assign(p, cone);
}

std::vector<std::vector<uint32_t>> HullBuilder::polygons() const {
    constexpr int kNone = -1;
    std::vector<int> group(faces_.size(), kNone);
    std::vector<std::vector<uint32_t>> result;
    for (uint32_t seed = 0; seed < faces_.size(); ++seed) {
        if (!faces_[seed].alive || group[seed] != kNone) continue;
        const int id = static_cast<int>(seed);
        const Triangle& plane = faces_[seed];
        // Region growing against the seed's plane, so long gentle curvature never chains together.
        std::vector<uint32_t> members{seed};
        group[seed] = id;
        for (size_t m = 0; m < members.size(); ++m) {
            const Triangle& t = faces_[members[m]];
            for (int k = 0; k < 3; ++k) {
                const uint32_t next = find_face(t.v[(k + 1) % 3], t.v[k]);
                if (group[next] != kNone || dot(faces_[next].normal, plane.normal) <= 0) continue;
                bool coplanar = true;
                for (uint32_t v : faces_[next].v)
                    coplanar = coplanar && std::fabs(dot(plane.normal, points_[v]) - plane.offset) <= tol_;
                if (!coplanar) continue;
                group[next] = id;
                members.push_back(next);
            }
        }
        // The boundary of the group, walked along its CCW directed edges.
        std::unordered_map<uint32_t, uint32_t> next_vertex;
        bool simple = true;
        for (uint32_t f : members) {
            const Triangle& t = faces_[f];
            for (int k = 0; k < 3; ++k) {
                const uint32_t from = t.v[k], to = t.v[(k + 1) % 3];
                if (group[find_face(to, from)] != id) simple = next_vertex.emplace(from, to).second && simple;
            }
        }
        std::vector<uint32_t> loop;
        if (simple && !next_vertex.empty()) loop.push_back(next_vertex.begin()->first);
        while (!loop.empty() && loop.size() <= next_vertex.size()) {
            auto to = next_vertex.find(loop.back());
            if (to == next_vertex.end() || to->second == loop.front()) break;
            loop.push_back(to->second);
        }
        const bool closed = !loop.empty() && next_vertex.count(loop.back()) &&
                            next_vertex.at(loop.back()) == loop.front();
        if (simple && closed && loop.size() == next_vertex.size()) {
            result.push_back(std::move(loop));
        } else {
            // Not a disk (numerical trouble): keep its triangles rather than a wrong polygon.
            for (uint32_t f : members) result.push_back({faces_[f].v.begin(), faces_[f].v.end()});
        }
    }
    return result;
}

// Drops vertices lying on the straight edge between their neighbours.
void drop_collinear(const std::vector<Vec3>& points, std::vector<uint32_t>& loop, double tol) {
    for (size_t i = 0; i < loop.size() && loop.size() > 3;) {
        const Vec3& prev = points[loop[(i + loop.size() - 1) % loop.size()]];
        const Vec3& here = points[loop[i]];
        const Vec3& next = points[loop[(i + 1) % loop.size()]];
        const Vec3 chord = sub(next, prev);
        const double length = norm(chord);
        if (length > 0 && norm(cross(sub(here, prev), chord)) / length <= tol) {
            loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
        } else {
            ++i;
        }
    }
}

// ODE checks a face's winding on its first three vertices alone, and a nearly straight corner
// there could read as clockwise by rounding: such a loop starts at its widest corner instead
// (any other keeps its order, and the worlds of scenes that never had one stay as they were).
void start_at_a_wide_corner(const std::vector<Vec3>& points, std::vector<uint32_t>& loop) {
    auto corner_area = [&](size_t i) {
        const Vec3& a = points[loop[i]];
        return norm(cross(sub(points[loop[(i + 1) % loop.size()]], a), sub(points[loop[(i + 2) % loop.size()]], a)));
    };
    size_t best = 0;
    for (size_t i = 1; i < loop.size(); ++i)
        if (corner_area(i) > corner_area(best)) best = i;
    if (corner_area(0) >= kNarrowCornerFraction * corner_area(best)) return;
    std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(best), loop.end());
}

// The hull of `input` built with `tol`, as polygons with unit planes.
ConvexHull build_hull(const std::vector<Vec3>& input, const Vec3& center, double tol) {
    std::vector<Vec3> centred(input.size());
    for (size_t i = 0; i < input.size(); ++i) centred[i] = sub(input[i], center);
    HullBuilder builder(std::move(centred), tol);
    builder.build();

    ConvexHull hull;
    std::unordered_map<uint32_t, uint32_t> renumbered;
    for (std::vector<uint32_t> loop : builder.polygons()) {
        drop_collinear(builder.points(), loop, tol);
        start_at_a_wide_corner(builder.points(), loop);
        const Vec3 n = newell_normal(builder.points(), loop);
        const Vec3 unit = scale(n, 1.0 / norm(n));
        double offset = 0;
        for (uint32_t& v : loop) {
            offset += dot(unit, input[v]);
            auto [it, inserted] = renumbered.emplace(v, static_cast<uint32_t>(hull.points.size()));
            if (inserted) hull.points.push_back(input[v]);
            v = it->second;
        }
        hull.planes.push_back({unit[0], unit[1], unit[2], offset / static_cast<double>(loop.size())});
        hull.faces.push_back(std::move(loop));
    }
    return hull;
}

// Whether `hull` is closed (every edge in two faces, once each way; V - E + F = 2) and not folded:
// every input point on or inside every face's plane, within `slack`. A face folded over by
// rounding points inwards, and most of the body then lies outside it.
bool is_closed_and_unfolded(const ConvexHull& hull, const std::vector<Vec3>& input, double slack) {
    std::unordered_map<uint64_t, int> edges;
    for (size_t f = 0; f < hull.faces.size(); ++f) {
        const auto& face = hull.faces[f];
        if (face.size() < 3) return false;
        for (size_t i = 0; i < face.size(); ++i)
            if (!edges.emplace(edge_key(face[i], face[(i + 1) % face.size()]), 1).second) return false;
        const Vec3 n{hull.planes[f][0], hull.planes[f][1], hull.planes[f][2]};
        for (const Vec3& p : input)
            if (dot(n, p) - hull.planes[f][3] > slack) return false;
    }
    for (const auto& [key, used] : edges)
        if (!edges.count((key << 32) | (key >> 32))) return false;
    const long euler = static_cast<long>(hull.points.size()) - static_cast<long>(edges.size() / 2) +
                       static_cast<long>(hull.faces.size());
    return euler == 2;
}

// Tolerances tried in turn, as fractions of the cloud's half-diagonal. The first is far below any
// modelling detail; clouds with near-duplicate points (a mesh's seam, float coordinates, a grown
// hull's bevels) can fold a hull built that fine, and a coarser one merges them. The last is
// 10 micrometres on a 1 m body.
constexpr double kRelativeTolerances[] = {kRelativeTolerance, 1e-7, 1e-6, 1e-5};
// How far (a fraction of the half-diagonal) a point may stand outside a face of a hull that is not
// folded: merging coplanar triangles tilts a face by rounding, a fold by the body's size.
constexpr double kFoldSlack = 1e-5;

}  // namespace

ConvexHull compute_convex_hull(const std::vector<double>& xyz) {
    const std::vector<Vec3> input = read_points(xyz);
    double half_diagonal = 0;
    const Vec3 center = bounds_center(input, half_diagonal);
    std::string trouble;
    for (const double relative : kRelativeTolerances) {
        const double tol = relative * half_diagonal;
        try {
            ConvexHull hull = build_hull(input, center, tol);
            if (is_closed_and_unfolded(hull, input, std::max(4 * tol, kFoldSlack * half_diagonal))) return hull;
            trouble = "folded or open";
        } catch (const FoldedHull& error) {
            trouble = error.what();
        }
    }
    throw GeometryError("convex hull: numerical breakdown at every tolerance (" + trouble + ")");
}

std::vector<double> thicken_flat_points(const std::vector<double>& xyz) {
    const size_t n = xyz.size() / 3;
    if (n < 3 || xyz.size() % 3 != 0) return xyz;
    auto point = [&](size_t i) { return Vec3{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}; };
    Vec3 lo = point(0), hi = point(0);
    for (size_t i = 1; i < n; ++i)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], xyz[3 * i + k]), hi[k] = std::max(hi[k], xyz[3 * i + k]);
    const double tol = kRelativeTolerance * norm(sub(hi, lo)) / 2;
    // A plane through the point farthest from the first and the one farthest from that line.
    size_t b = 0, c = 0;
    for (size_t i = 1; i < n; ++i)
        if (norm(sub(point(i), point(0))) > norm(sub(point(b), point(0)))) b = i;
    const Vec3 ab = sub(point(b), point(0));
    if (norm(ab) <= tol) return xyz;
    for (size_t i = 1; i < n; ++i)
        if (norm(cross(ab, sub(point(i), point(0)))) > norm(cross(ab, sub(point(c), point(0))))) c = i;
    const Vec3 normal = cross(ab, sub(point(c), point(0)));
    if (norm(normal) / norm(ab) <= tol) return xyz;  // collinear: no plane to thicken
    const Vec3 unit = scale(normal, 1 / norm(normal));
    for (size_t i = 0; i < n; ++i)
        if (std::fabs(dot(unit, sub(point(i), point(0)))) > tol) return xyz;  // spans a volume
    std::vector<double> out;
    out.reserve(2 * xyz.size());
    for (const double side : {-kFlatShapeHalfThickness_m, kFlatShapeHalfThickness_m})
        for (size_t i = 0; i < n; ++i) {
            const Vec3 p = add(point(i), scale(unit, side));
            out.insert(out.end(), p.begin(), p.end());
        }
    return out;
}

bool mesh_fills_its_hull(const std::vector<double>& vertices, const std::vector<uint32_t>& triangles) {
    const std::vector<double> solid = thicken_flat_points(vertices);
    const bool flat = solid.size() != vertices.size();
    ConvexHull hull;
    try {
        hull = compute_convex_hull(solid);
    } catch (const GeometryError&) {
        return false;
    }
    auto vertex = [&](uint32_t i) { return Vec3{vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]}; };
    auto face_area = [&](const std::vector<uint32_t>& face) {
        double area = 0;
        for (size_t i = 1; i + 1 < face.size(); ++i)
            area += norm(cross(sub(hull.points[face[i]], hull.points[face[0]]),
                               sub(hull.points[face[i + 1]], hull.points[face[0]]))) / 2;
        return area;
    };
    double extent = 0;
    for (const Vec3& p : hull.points) extent = std::max(extent, norm(p));
    const double tol = 1e-7 * (1 + extent);
    std::vector<double> covered(hull.faces.size(), 0.0);
    double total = 0;
    for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const Vec3 a = vertex(triangles[t]), b = vertex(triangles[t + 1]), c = vertex(triangles[t + 2]);
        const double area = norm(cross(sub(b, a), sub(c, a))) / 2;
        total += area;
        if (flat) continue;
        size_t f = 0;
        for (; f < hull.faces.size(); ++f) {
            const Vec3 n{hull.planes[f][0], hull.planes[f][1], hull.planes[f][2]};
            const double d = hull.planes[f][3];
            if (std::fabs(dot(n, a) - d) <= tol && std::fabs(dot(n, b) - d) <= tol && std::fabs(dot(n, c) - d) <= tol) break;
        }
        if (f == hull.faces.size()) return false;  // inside the hull: not convex
        covered[f] += area;
    }
    if (flat) {
        // The triangles lie in the slab's mid-plane: together they must cover its outline once.
        double outline = 0;
        for (const auto& face : hull.faces) outline = std::max(outline, face_area(face));
        return std::fabs(total - outline) <= 1e-4 * outline;
    }
    for (size_t f = 0; f < hull.faces.size(); ++f) {
        const double area = face_area(hull.faces[f]);
        if (std::fabs(covered[f] - area) > 1e-4 * std::max(area, 1e-12)) return false;
    }
    return true;
}

}  // namespace mwb
