#include "query/PathTree.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mwb {
namespace {

// A query over the whole path needs no times until it finds a touch.
bool whole_path(double t_lo, double t_hi) {
    return t_lo == -std::numeric_limits<double>::infinity() && t_hi == std::numeric_limits<double>::infinity();
}

constexpr int kMaxDepth = 3;
constexpr uint32_t kMinSegmentsToSplit = 8;
constexpr uint32_t kCovarianceSamples = 32;
constexpr double kRootAxesTolerance = 1e-12, kChildAxesTolerance = 1e-6;

// Eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations; columns of the result.
// The axes only need to be good, not exact: any axes give a box that holds the points, and they
// are stored to 1/32767 (the root) or 1/127. The solver stops once the off-diagonal's square is
// `tolerance` times the diagonal's, an angle of about its square root.
std::array<Vec3, 3> principal_axes(std::array<double, 9> a, double tolerance) {
    std::array<double, 9> v{1, 0, 0, 0, 1, 0, 0, 0, 1};
    const double scale2 = a[0] * a[0] + a[4] * a[4] + a[8] * a[8];
    for (int sweep = 0; sweep < 12; ++sweep) {
        const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
        if (off <= tolerance * scale2 || off < 1e-30) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                const double apq = a[3 * p + q];
                if (std::fabs(apq) < 1e-300) continue;
                const double theta = (a[3 * q + q] - a[3 * p + p]) / (2 * apq);
                const double t = (theta >= 0 ? 1 : -1) / (std::fabs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; ++k) {  // A <- J^T A J
                    const double akp = a[3 * k + p], akq = a[3 * k + q];
                    a[3 * k + p] = c * akp - s * akq;
                    a[3 * k + q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[3 * p + k], aqk = a[3 * q + k];
                    a[3 * p + k] = c * apk - s * aqk;
                    a[3 * q + k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = v[3 * k + p], vkq = v[3 * k + q];
                    v[3 * k + p] = c * vkp - s * vkq;
                    v[3 * k + q] = s * vkp + c * vkq;
                }
            }
        }
    }
    Vec3 x{v[0], v[3], v[6]}, y{v[1], v[4], v[7]};
    x = scale(x, 1 / norm(x));
    y = sub(y, scale(x, dot(x, y)));
    const double ly = norm(y);
    y = ly > 1e-12 ? scale(y, 1 / ly) : (std::fabs(x[0]) < 0.9 ? cross(x, {1, 0, 0}) : cross(x, {0, 1, 0}));
    y = scale(y, 1 / norm(y));
    return {x, y, cross(x, y)};
}

// The unit quaternion turning the world axes onto `axes` (a right-handed orthonormal frame).
Quat rotation_onto(const std::array<Vec3, 3>& axes) {
    // m[r][c]: column c is axes[c].
    const double m00 = axes[0][0], m11 = axes[1][1], m22 = axes[2][2];
    const double trace = m00 + m11 + m22;
    Quat q;
    if (trace > 0) {
        const double s = 2 * std::sqrt(1 + trace);
        q = {s / 4, (axes[1][2] - axes[2][1]) / s, (axes[2][0] - axes[0][2]) / s, (axes[0][1] - axes[1][0]) / s};
    } else if (m00 > m11 && m00 > m22) {
        const double s = 2 * std::sqrt(1 + m00 - m11 - m22);
        q = {(axes[1][2] - axes[2][1]) / s, s / 4, (axes[1][0] + axes[0][1]) / s, (axes[2][0] + axes[0][2]) / s};
    } else if (m11 > m22) {
        const double s = 2 * std::sqrt(1 + m11 - m00 - m22);
        q = {(axes[2][0] - axes[0][2]) / s, (axes[1][0] + axes[0][1]) / s, s / 4, (axes[2][1] + axes[1][2]) / s};
    } else {
        const double s = 2 * std::sqrt(1 + m22 - m00 - m11);
        q = {(axes[0][1] - axes[1][0]) / s, (axes[2][0] + axes[0][2]) / s, (axes[2][1] + axes[1][2]) / s, s / 4};
    }
    return quat_normalized(q);
}

// Components of a quaternion (any length, not zero) to the columns of its rotation matrix: the
// images of the world axes. With s = 2 / |q|² one division does what normalizing would.
std::array<Vec3, 3> axes_from(double w, double x, double y, double z) {
    const double s = 2 / (w * w + x * x + y * y + z * z);
    return {Vec3{1 - s * (y * y + z * z), s * (x * y + w * z), s * (x * z - w * y)},
            Vec3{s * (x * y - w * z), 1 - s * (x * x + z * z), s * (y * z + w * x)},
            Vec3{s * (x * z + w * y), s * (y * z - w * x), 1 - s * (x * x + y * y)}};
}

std::array<Vec3, 3> axes_of(const PathBox& box) {
    return axes_from(box.rotation[0], box.rotation[1], box.rotation[2], box.rotation[3]);
}

std::array<Vec3, 3> axes_of(const ChildBox& box) {
    return axes_from(box.rotation[0], box.rotation[1], box.rotation[2], box.rotation[3]);
}

Vec3 center_of(const PathBox& box) { return {box.center[0], box.center[1], box.center[2]}; }
Vec3 half_of(const PathBox& box) { return {box.half_extents[0], box.half_extents[1], box.half_extents[2]}; }

// A child box's centre and half extents, decoded the same way when it is built and when it is
// tested.
Vec3 center_of(const ChildBox& box, const Vec3& parent_center, double parent_reach) {
    return {parent_center[0] + parent_reach * (box.offset[0] / 32767.0),
            parent_center[1] + parent_reach * (box.offset[1] / 32767.0),
            parent_center[2] + parent_reach * (box.offset[2] / 32767.0)};
}

constexpr double kHalfScale = 4.0;  // a child's half extents are at most this many parent reaches

Vec3 half_of(const ChildBox& box, double parent_reach) {
    const double unit = kHalfScale * parent_reach / 65535.0;
    return {unit * box.half[0], unit * box.half[1], unit * box.half[2]};
}

// The principal axes of points first..last as a unit quaternion (mean and covariance in one pass).
// The axes need only be good, so a long run's covariance is taken over every step-th point.
Quat fitted_rotation(const Vec3* point, uint32_t first, uint32_t last, double tolerance, Vec3& mean) {
    Vec3 sum{0, 0, 0};
    std::array<double, 6> products{};  // xx, xy, xz, yy, yz, zz
    const Vec3 origin = point[first];  // offsets from a path point keep the sums well conditioned
    const uint32_t step = std::max<uint32_t>(1, (last - first) / kCovarianceSamples);
    double n = 0;
    for (uint32_t k = first; k <= last; k += step, ++n) {
        const Vec3 d = sub(point[k], origin);
        sum = add(sum, d);
        products[0] += d[0] * d[0];
        products[1] += d[0] * d[1];
        products[2] += d[0] * d[2];
        products[3] += d[1] * d[1];
        products[4] += d[1] * d[2];
        products[5] += d[2] * d[2];
    }
    const Vec3 m = scale(sum, 1 / n);
    mean = add(origin, m);
    const std::array<double, 9> covariance{
        products[0] - n * m[0] * m[0], products[1] - n * m[0] * m[1], products[2] - n * m[0] * m[2],
        products[1] - n * m[0] * m[1], products[3] - n * m[1] * m[1], products[4] - n * m[1] * m[2],
        products[2] - n * m[0] * m[2], products[4] - n * m[1] * m[2], products[5] - n * m[2] * m[2]};
    return rotation_onto(principal_axes(covariance, tolerance));
}

// A leaf's axes without a covariance: along its chord, then towards its middle point, which for a
// short run of a path is about what the principal axes are.
Quat chord_rotation(const Vec3* point, uint32_t first, uint32_t last) {
    Vec3 x = sub(point[last], point[first]);
    const double length = norm(x);
    x = length > 1e-9 ? scale(x, 1 / length) : Vec3{1, 0, 0};
    Vec3 y = sub(point[first + (last - first) / 2], point[first]);
    y = sub(y, scale(x, dot(x, y)));
    const double height = norm(y);
    y = height > 1e-9 ? scale(y, 1 / height) : (std::fabs(x[0]) < 0.9 ? cross(x, {1, 0, 0}) : cross(x, {0, 1, 0}));
    y = scale(y, 1 / norm(y));
    return rotation_onto({x, y, cross(x, y)});
}

// How far points first..last lie along each of `axes` from `from` (lo, hi), and the centre of
// that box.
struct Extents {
    Vec3 lo, hi, center;
};

Extents extents_along(const Vec3* point, uint32_t first, uint32_t last, const Vec3& from,
                      const std::array<Vec3, 3>& axes) {
    Extents out{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}, from};
    for (uint32_t k = first; k <= last; ++k) {
        const Vec3 d = sub(point[k], from);
        for (int a = 0; a < 3; ++a) {
            const double along = dot(d, axes[a]);
            out.lo[a] = std::min(out.lo[a], along);
            out.hi[a] = std::max(out.hi[a], along);
        }
    }
    for (int a = 0; a < 3; ++a) out.center = add(out.center, scale(axes[a], (out.lo[a] + out.hi[a]) / 2));
    return out;
}

// Padding for the arithmetic of decoding and testing a box of this half extent at this scale.
double padded(double half, double scale_m) { return half * (1 + 1e-6) + 1e-6 * (1 + scale_m); }

}  // namespace

BoxSide PathView::box_side(const PathBox& box, const Frustum& frustum, double radius) {
    BoxSide out;
    out.side = frustum.classify_box(center_of(box), axes_of(box), half_of(box), radius, &out.crossing);
    return out;
}

bool PathView::splits(uint32_t first, uint32_t last, int depth) {
    return depth < kMaxDepth && last - first >= kMinSegmentsToSplit;
}

uint32_t PathView::subtree_nodes(uint32_t first, uint32_t last, int depth) {
    if (!splits(first, last, depth)) return 1;
    const uint32_t middle = first + (last - first) / 2;
    return 1 + subtree_nodes(first, middle, depth + 1) + subtree_nodes(middle, last, depth + 1);
}

PathView::PathView(const PathBox* root, const ChildBox* children, PathPoints points, uint32_t stride,
                   uint32_t last_frame, double record_hz, double hold_until_s)
    : root_(root),
      children_(children),
      block_(points.block),
      point_count_(points.count),
      stride_(std::max<uint32_t>(1, stride)),
      last_frame_(last_frame),
      record_hz_(record_hz) {
    if (point_count_ > 0) hold_end_s_ = std::max(time_of(point_count_ - 1), hold_until_s);
}

uint32_t PathView::child_count(uint32_t point_count) {
    return point_count == 0 ? 0 : subtree_nodes(0, point_count - 1, 0) - 1;
}

void PathView::build_boxes(PathPoints points, PathBox& root, std::vector<ChildBox>& children) {
    // Decoded once: every level of the tree passes over the points.
    thread_local std::vector<Vec3> decoded;
    decoded.resize(points.count);
    const quantized::Header header = quantized::header(points.block);
    for (uint32_t k = 0; k < points.count; ++k) decoded[k] = quantized::point(header, points.block, k);
    const Vec3* point = decoded.data();
    const uint32_t last = points.count - 1;
    Vec3 mean;
    const Quat rotation = fitted_rotation(point, 0, last, kRootAxesTolerance, mean);
    for (int c = 0; c < 4; ++c) root.rotation[c] = static_cast<int16_t>(std::lround(rotation[c] * 32767.0));
    const std::array<Vec3, 3> axes = axes_of(root);
    const Extents extents = extents_along(point, 0, last, mean, axes);
    const Vec3& lo = extents.lo;
    const Vec3& hi = extents.hi;
    const Vec3& center = extents.center;
    // Stored in single precision: around the rounded centre a point reaches at most half the
    // extent plus the rounding shift along each axis.
    for (int a = 0; a < 3; ++a) root.center[a] = static_cast<float>(center[a]);
    const Vec3 shift = sub(center_of(root), center);
    Vec3 half{};
    for (int a = 0; a < 3; ++a) half[a] = (hi[a] - lo[a]) / 2 + std::fabs(dot(shift, axes[a]));
    const double reach = norm(half);
    for (int a = 0; a < 3; ++a) root.half_extents[a] = static_cast<float>(padded(half[a], reach));
    build_children(point, 0, last, 0, center_of(root), norm(half_of(root)), children);
}

void PathView::build_children(const Vec3* points, uint32_t first, uint32_t last, int depth, const Vec3& center,
                              double reach, std::vector<ChildBox>& out) {
    if (!splits(first, last, depth)) return;
    const uint32_t middle = first + (last - first) / 2;  // children share the middle point
    for (const auto& [lo, hi] : {std::pair{first, middle}, std::pair{middle, last}}) {
        const ChildBox child = fit_child(points, lo, hi, !splits(lo, hi, depth + 1), center, reach);
        out.push_back(child);
        build_children(points, lo, hi, depth + 1, center_of(child, center, reach), norm(half_of(child, reach)), out);
    }
}

ChildBox PathView::fit_child(const Vec3* point, uint32_t first, uint32_t last, bool leaf, const Vec3& parent_center,
                             double parent_reach) {
    ChildBox box{};
    Vec3 mean = point[first];  // any point of the run will do to measure the extents from
    const Quat rotation =
        leaf ? chord_rotation(point, first, last) : fitted_rotation(point, first, last, kChildAxesTolerance, mean);
    for (int c = 0; c < 4; ++c) box.rotation[c] = static_cast<int8_t>(std::lround(rotation[c] * 127.0));
    const std::array<Vec3, 3> axes = axes_of(box);
    // The centre of the points' extents along the axes, as the parent's reach allows it to be put:
    // it lies within the parent's box, so within one reach of the parent's centre.
    const Extents extents = extents_along(point, first, last, mean, axes);
    const Vec3& lo = extents.lo;
    const Vec3& hi = extents.hi;
    const Vec3& center = extents.center;
    for (int a = 0; a < 3; ++a)
        box.offset[a] = static_cast<int16_t>(
            std::clamp(std::lround((center[a] - parent_center[a]) / parent_reach * 32767.0), -32767L, 32767L));
    // Half extents around the centre as decoded (the points' extents shifted by where it lies
    // from the mean), rounded up to the next step: no point is outside.
    const Vec3 shift = sub(center_of(box, parent_center, parent_reach), mean);
    Vec3 half{};
    for (int a = 0; a < 3; ++a) {
        const double along = dot(shift, axes[a]);
        half[a] = std::max(std::fabs(lo[a] - along), std::fabs(hi[a] - along));
    }
    const double unit = kHalfScale * parent_reach / 65535.0;
    for (int a = 0; a < 3; ++a) {
        const double needed = padded(half[a], norm(half));
        const double steps = std::min(65535.0, std::ceil(needed / unit));
        box.half[a] = static_cast<uint16_t>(steps);
        if (half_of(box, parent_reach)[a] < needed && box.half[a] < 65535) ++box.half[a];
    }
    return box;
}

double PathView::end_of(uint32_t last_point) const {
    return last_point + 1 == point_count() ? hold_end_s_ : time_of(last_point);
}

double PathView::time_of(size_t k) const {
    return static_cast<double>(std::min<uint64_t>(uint64_t{k} * stride_, last_frame_)) / record_hz_;
}

PathTree::PathTree(const std::vector<float>& points, uint32_t stride, uint32_t last_frame, double record_hz,
                   double hold_until_s) {
    const auto count = static_cast<uint32_t>(points.size() / 3);
    held_block_ = quantized::encode_flat(points);
    const PathPoints own{held_block_.data(), count};
    if (count > 0) {
        held_children_.reserve(child_count(count));
        build_boxes(own, held_root_, held_children_);
    }
    static_cast<PathView&>(*this) =
        PathView(&held_root_, held_children_.data(), own, stride, last_frame, record_hz, hold_until_s);
}

PathTree::PathTree(const PathTree& other)
    : PathView(other), held_block_(other.held_block_), held_root_(other.held_root_),
      held_children_(other.held_children_) {
    rebind(&held_root_, held_children_.data(), held_block_.data());
}

PathTree::PathTree(PathTree&& other) noexcept
    : PathView(other), held_block_(std::move(other.held_block_)), held_root_(other.held_root_),
      held_children_(std::move(other.held_children_)) {
    rebind(&held_root_, held_children_.data(), held_block_.data());
}

bool PathView::touches(const Frustum& frustum, const TimeWindow& window, double radius, const BoxSide* root) const {
    return first_touch_time(frustum, window, radius, root) >= 0;
}

bool PathView::touches_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const {
    return first_touch_time_brute_force(frustum, window, radius) >= 0;
}

double PathView::segments_first_touch(uint32_t first, uint32_t last, const Frustum& frustum, double t_lo,
                                      double t_hi, double radius, unsigned planes) const {
    // Each point's side of every plane is found once (neighbouring segments share it): a segment
    // with both ends beyond one plane cannot touch, which is how Frustum::first_touch would answer.
    const quantized::Header header = quantized::header(block_);
    const auto point = [&](uint32_t k) { return quantized::point(header, block_, k); };
    const auto outside = [&](uint32_t k) {
        const Vec3 p = point(k);
        unsigned bits = 0;
        for (unsigned rest = planes; rest != 0; rest &= rest - 1) {
            const int i = __builtin_ctz(rest);
            bits |= unsigned(frustum.planes[static_cast<size_t>(i)].distance(p) + radius < 0) << i;
        }
        return bits;
    };
    unsigned outside_next = first < last ? outside(first) : 0;
    for (uint32_t k = first; k < last; ++k) {
        const unsigned outside_here = outside_next;
        outside_next = outside(k + 1);
        if (outside_here & outside_next) continue;
        const double ta = time_of(k), tb = time_of(k + 1);
        if (tb < t_lo || ta > t_hi) continue;
        // The part of the segment inside the time window (linear in time between samples).
        const double span = tb - ta;
        const double u0 = span > 0 ? std::max(0.0, (t_lo - ta) / span) : 0.0;
        const double u1 = span > 0 ? std::min(1.0, (t_hi - ta) / span) : 1.0;
        const double u = frustum.first_touch(point(k), point(k + 1), u0, u1, radius);
        if (u >= 0) return ta + u * span;
    }
    // The held last pose (the last point from its own time to the end of the hold) comes after
    // every segment.
    if ((first == last || last + 1 == point_count()) && time_of(last) <= t_hi && end_of(last) >= t_lo &&
        frustum.touches_segment(point(last), point(last), 0, 1, radius))
        return std::max(time_of(last), t_lo);
    return std::numeric_limits<double>::infinity();
}

double PathView::node_first_touch(uint32_t node, uint32_t first, uint32_t last, int depth,
                                  const Vec3& parent_center, double parent_reach, unsigned planes,
                                  const Frustum& frustum, double t_lo, double t_hi, double radius) const {
    if (!whole_path(t_lo, t_hi) && (end_of(last) < t_lo || time_of(first) > t_hi))
        return std::numeric_limits<double>::infinity();
    // A leaf's points are needed if its box crosses: they load while the box is tested.
    if (!splits(first, last, depth)) {
        __builtin_prefetch(block_);
        __builtin_prefetch(block_ + quantized::kHeaderWords + 3 * first);
    }
    const ChildBox& box = children_[node - 1];
    const Vec3 center = center_of(box, parent_center, parent_reach);
    const Vec3 half = half_of(box, parent_reach);
    BoxSide side;
    // Only the planes the parent crosses: its points, so this node's, are inside the others.
    side.side = frustum.classify_box(center, axes_of(box), half, radius, &side.crossing, planes);
    return classified_first_touch(side, node, first, last, depth, center, half, frustum, t_lo, t_hi, radius);
}

double PathView::classified_first_touch(BoxSide side, uint32_t node, uint32_t first, uint32_t last, int depth,
                                        const Vec3& center, const Vec3& half, const Frustum& frustum, double t_lo,
                                        double t_hi, double radius) const {
    if (side.side < 0) return std::numeric_limits<double>::infinity();
    if (!whole_path(t_lo, t_hi) && (end_of(last) < t_lo || time_of(first) > t_hi))
        return std::numeric_limits<double>::infinity();
    // Wholly inside: the path touches from the first moment of the node within the window.
    if (side.side > 0) return std::max(time_of(first), t_lo);
    if (!splits(first, last, depth))
        return segments_first_touch(first, last, frustum, t_lo, t_hi, radius, side.crossing);
    // The first child holds the earlier part of the path; the second follows its subtree.
    const uint32_t middle = first + (last - first) / 2;
    const double reach = norm(half);
    const double early =
        node_first_touch(node + 1, first, middle, depth + 1, center, reach, side.crossing, frustum, t_lo, t_hi, radius);
    if (std::isfinite(early)) return early;
    return node_first_touch(node + 1 + subtree_nodes(first, middle, depth + 1), middle, last, depth + 1, center, reach,
                            side.crossing, frustum, t_lo, t_hi, radius);
}

double PathView::first_touch_time(const Frustum& frustum, const TimeWindow& window, double radius,
                                  const BoxSide* root) const {
    if (point_count_ == 0) return -1;
    const double lo = window.empty() ? -std::numeric_limits<double>::infinity() : window.lo_s;
    const double hi = window.empty() ? std::numeric_limits<double>::infinity() : window.hi_s;
    const auto last = static_cast<uint32_t>(point_count() - 1);
    const BoxSide side = root ? *root : box_side(*root_, frustum, radius);
    const double t =
        classified_first_touch(side, 0, 0, last, 0, center_of(*root_), half_of(*root_), frustum, lo, hi, radius);
    return std::isfinite(t) ? t : -1;
}

double PathView::first_touch_time_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const {
    if (point_count() == 0) return -1;
    const double lo = window.empty() ? -std::numeric_limits<double>::infinity() : window.lo_s;
    const double hi = window.empty() ? std::numeric_limits<double>::infinity() : window.hi_s;
    const double t = segments_first_touch(0, static_cast<uint32_t>(point_count() - 1), frustum, lo, hi, radius);
    return std::isfinite(t) ? t : -1;
}

double PathView::first_time_inside(const Frustum& frustum) const {
    for (size_t k = 0; k < point_count(); ++k) {
        const Vec3 p = point(k);
        if (frustum.touches_segment(p, p, 0, 1, 0)) return time_of(k);
    }
    return -1;
}

}  // namespace mwb
