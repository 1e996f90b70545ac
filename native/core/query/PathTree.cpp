#include "query/PathTree.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mwb {
namespace {

constexpr int kMaxDepth = 3;
constexpr uint32_t kMinSegmentsToSplit = 8;

// Eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi rotations; columns of the result.
std::array<Vec3, 3> principal_axes(std::array<double, 9> a) {
    std::array<double, 9> v{1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int sweep = 0; sweep < 12; ++sweep) {
        const double off = a[1] * a[1] + a[2] * a[2] + a[5] * a[5];
        if (off < 1e-30) break;
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

}  // namespace

PathTree::PathTree(std::vector<float> points, uint32_t stride, uint32_t last_frame, double record_hz,
                   double hold_until_s)
    : stride_(std::max<uint32_t>(1, stride)), last_frame_(last_frame), record_hz_(record_hz) {
    quantize(points);
    if (point_count() > 0) {
        hold_end_s_ = std::max(time_of(point_count() - 1), hold_until_s);
        build(0, static_cast<uint32_t>(point_count() - 1), 0);
    }
}

void PathTree::quantize(const std::vector<float>& points) {
    const size_t n = points.size() / 3;
    points_.resize(n * 3);
    if (n == 0) return;
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (size_t k = 0; k < n; ++k)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], double(points[3 * k + a]));
            hi[a] = std::max(hi[a], double(points[3 * k + a]));
        }
    for (int a = 0; a < 3; ++a) {
        origin_[a] = lo[a];
        step_[a] = (hi[a] - lo[a]) / 65535.0;
        for (size_t k = 0; k < n; ++k)
            points_[3 * k + a] = step_[a] > 0 ? static_cast<uint16_t>(std::lround((points[3 * k + a] - lo[a]) / step_[a])) : 0;
    }
}

double PathTree::end_of(uint32_t last_point) const {
    return last_point + 1 == point_count() ? hold_end_s_ : time_of(last_point);
}

double PathTree::time_of(size_t k) const {
    return static_cast<double>(std::min<uint64_t>(uint64_t{k} * stride_, last_frame_)) / record_hz_;
}

size_t PathTree::memory_bytes() const {
    return sizeof(*this) + points_.capacity() * sizeof(uint16_t) + nodes_.capacity() * sizeof(Node);
}

int32_t PathTree::build(uint32_t first, uint32_t last, int depth) {
    const auto index = static_cast<int32_t>(nodes_.size());
    nodes_.push_back({});
    // Principal axes of the points, then the box of their extents along them.
    Vec3 mean{0, 0, 0};
    const double n = last - first + 1;
    for (uint32_t k = first; k <= last; ++k) mean = add(mean, point(k));
    mean = scale(mean, 1 / n);
    std::array<double, 9> covariance{};
    for (uint32_t k = first; k <= last; ++k) {
        const Vec3 d = sub(point(k), mean);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) covariance[3 * r + c] += d[r] * d[c];
    }
    const std::array<Vec3, 3> axes = principal_axes(covariance);
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (uint32_t k = first; k <= last; ++k) {
        const Vec3 d = sub(point(k), mean);
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], dot(d, axes[a]));
            hi[a] = std::max(hi[a], dot(d, axes[a]));
        }
    }
    Node node;
    Vec3 center = mean;
    for (int a = 0; a < 3; ++a) center = add(center, scale(axes[a], (lo[a] + hi[a]) / 2));
    // Stored in single precision: the box is re-measured around the rounded centre and axes, and
    // padded for the rounding of the axes, so every point stays inside the stored box.
    for (int a = 0; a < 3; ++a) {
        node.center[a] = static_cast<float>(center[a]);
        for (int c = 0; c < 3; ++c) node.axes[3 * a + c] = static_cast<float>(axes[a][c]);
    }
    const Vec3 stored_center{node.center[0], node.center[1], node.center[2]};
    double reach = 0;
    for (uint32_t k = first; k <= last; ++k) reach = std::max(reach, norm(sub(point(k), stored_center)));
    for (int a = 0; a < 3; ++a) {
        const Vec3 stored_axis{node.axes[3 * a], node.axes[3 * a + 1], node.axes[3 * a + 2]};
        double extent = 0;
        for (uint32_t k = first; k <= last; ++k) extent = std::max(extent, std::fabs(dot(sub(point(k), stored_center), stored_axis)));
        node.half_extents[a] = static_cast<float>(extent * (1 + 1e-6) + 1e-6 * (1 + reach));
    }
    node.first_point = first;
    node.last_point = last;
    node.children[0] = node.children[1] = -1;
    if (depth < kMaxDepth && last - first >= kMinSegmentsToSplit) {
        const uint32_t middle = first + (last - first) / 2;  // children share the middle point
        node.children[0] = static_cast<int16_t>(build(first, middle, depth + 1));
        node.children[1] = static_cast<int16_t>(build(middle, last, depth + 1));
    }
    nodes_[static_cast<size_t>(index)] = node;
    return index;
}

bool PathTree::touches(const Frustum& frustum, const TimeWindow& window, double radius) const {
    return first_touch_time(frustum, window, radius) >= 0;
}

bool PathTree::touches_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const {
    return first_touch_time_brute_force(frustum, window, radius) >= 0;
}

double PathTree::segments_first_touch(uint32_t first, uint32_t last, const Frustum& frustum, double t_lo,
                                      double t_hi, double radius) const {
    for (uint32_t k = first; k < last; ++k) {
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

double PathTree::node_first_touch(int32_t index, const Frustum& frustum, double t_lo, double t_hi,
                                  double radius) const {
    const Node& node = nodes_[static_cast<size_t>(index)];
    const double start = time_of(node.first_point), end = end_of(node.last_point);
    if (end < t_lo || start > t_hi) return std::numeric_limits<double>::infinity();
    const int side = frustum.classify_box(
        {node.center[0], node.center[1], node.center[2]},
        {Vec3{node.axes[0], node.axes[1], node.axes[2]}, Vec3{node.axes[3], node.axes[4], node.axes[5]},
         Vec3{node.axes[6], node.axes[7], node.axes[8]}},
        {node.half_extents[0], node.half_extents[1], node.half_extents[2]}, radius);
    if (side < 0) return std::numeric_limits<double>::infinity();
    // Wholly inside: the path touches from the first moment of the node within the window.
    if (side > 0) return std::max(start, t_lo);
    if (node.children[0] < 0) return segments_first_touch(node.first_point, node.last_point, frustum, t_lo, t_hi, radius);
    // The first child holds the earlier part of the path.
    const double early = node_first_touch(node.children[0], frustum, t_lo, t_hi, radius);
    return std::isfinite(early) ? early : node_first_touch(node.children[1], frustum, t_lo, t_hi, radius);
}

double PathTree::first_touch_time(const Frustum& frustum, const TimeWindow& window, double radius) const {
    if (nodes_.empty()) return -1;
    const double lo = window.empty() ? -std::numeric_limits<double>::infinity() : window.lo_s;
    const double hi = window.empty() ? std::numeric_limits<double>::infinity() : window.hi_s;
    const double t = node_first_touch(0, frustum, lo, hi, radius);
    return std::isfinite(t) ? t : -1;
}

double PathTree::first_touch_time_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const {
    if (point_count() == 0) return -1;
    const double lo = window.empty() ? -std::numeric_limits<double>::infinity() : window.lo_s;
    const double hi = window.empty() ? std::numeric_limits<double>::infinity() : window.hi_s;
    const double t = segments_first_touch(0, static_cast<uint32_t>(point_count() - 1), frustum, lo, hi, radius);
    return std::isfinite(t) ? t : -1;
}

double PathTree::first_time_inside(const Frustum& frustum) const {
    for (size_t k = 0; k < point_count(); ++k) {
        const Vec3 p = point(k);
        if (frustum.touches_segment(p, p, 0, 1, 0)) return time_of(k);
    }
    return -1;
}

}  // namespace mwb
