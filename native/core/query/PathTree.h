#pragma once
// One body's centre-of-mass path (a polyline) in an oriented-bounding-box tree of depth <= 3
// with runs of segments at the leaves. A PathView queries a path whose boxes and points live
// elsewhere: the index keeps the boxes of a world's paths in one array and reads the points the
// library draws from, so ten thousand worlds do not hold every path twice. A PathTree owns both.
#include <array>
#include <cstdint>
#include <vector>

#include "query/Frustum.h"

namespace mwb {

/// A path's points owned elsewhere: flat (count, 3) float32.
struct PathPoints {
    const float* xyz = nullptr;
    uint32_t count = 0;
};

/// A time interval in seconds; the whole path when empty() (lo > hi).
struct TimeWindow {
    double lo_s = 1, hi_s = 0;
    bool empty() const { return lo_s > hi_s; }
};

/// An oriented box in 32 bytes: single-precision centre and extents, the axes as a rotation
/// quantized to 16 bits per component.
struct PathBox {
    std::array<float, 3> center;
    std::array<int16_t, 4> rotation;  ///< w, x, y, z of a unit quaternion, times 32767
    std::array<float, 3> half_extents;
};

/// Where a box lies against a frustum: side -1 wholly outside a plane, +1 wholly inside all, 0
/// otherwise, with a bit per plane (bit i: planes[i]) it is not wholly inside.
struct BoxSide {
    int side = 0;
    unsigned crossing = 0x3f;
};

class PathView {
public:
    /// A path without points: it touches nothing.
    PathView() = default;
    /// `boxes`: what build_boxes made of `points`. Point k is at time
    /// min(k·stride, last_frame) / record_hz; the last point is held from its time up to
    /// `hold_until_s` (a world that came to rest before the run's end stays where it rests).
    PathView(const PathBox* boxes, PathPoints points, uint32_t stride, uint32_t last_frame, double record_hz,
             double hold_until_s = 0);

    /// How many boxes the tree over `point_count` points has.
    static uint32_t box_count(uint32_t point_count);
    /// Appends the boxes of the tree over `points` to `out`, root first, depth first.
    static void build_boxes(PathPoints points, std::vector<PathBox>& out);

    /// Whether the path comes within `radius` of the frustum during `window` (whole path if
    /// the window is empty): whether it has a first touch. Uses the tree; the answer equals
    /// touches_brute_force exactly.
    /// `root`: box_side(root_box()) when the caller has it already, so the tree does not test it again.
    bool touches(const Frustum& frustum, const TimeWindow& window, double radius, const BoxSide* root = nullptr) const;
    /// The same answer by testing every segment; for tests and benchmarks.
    bool touches_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const;
    /// First time (seconds) the path is inside the frustum, or a negative value if never.
    double first_time_inside(const Frustum& frustum) const;
    /// Earliest time (seconds) within `window` at which the path comes within `radius` of the
    /// frustum, or a negative value if it does not: touches() with the moment it happens (between
    /// samples the path is linear in time). Uses the tree, visiting earlier runs first.
    double first_touch_time(const Frustum& frustum, const TimeWindow& window, double radius,
                            const BoxSide* root = nullptr) const;
    /// The same by testing every segment in order; for tests and benchmarks.
    double first_touch_time_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const;

    /// The root's oriented box, as the tree tests it; only for a path with points. Kept beside
    /// other paths' roots, it decides most queries without touching the tree.
    const PathBox& root_box() const { return boxes_[0]; }
    /// Where `box` (grown by `radius`) lies: wholly outside the frustum, the path does not touch
    /// it at any time, exactly as the tree would answer.
    static BoxSide box_side(const PathBox& box, const Frustum& frustum, double radius);

    size_t point_count() const { return point_count_; }
    /// Point k as given. Tree and brute force both see exactly these points.
    Vec3 point(size_t k) const { return {points_[3 * k], points_[3 * k + 1], points_[3 * k + 2]}; }
    double time_of(size_t k) const;
    /// Time up to which the path has a pose: its last point's time, or later while that pose is held.
    double end_time_s() const { return hold_end_s_; }

protected:
    /// Points the view at a copy of what it viewed.
    void rebind(const PathBox* boxes, const float* points) {
        boxes_ = boxes;
        points_ = points;
    }

private:
    // A node is a PathBox, measured around the axes as the query rebuilds them, and padded for the
    // single-precision rounding, so every point stays inside it. Which points a node covers and
    // whether it has children follow from the point count (nodes are in depth-first order, each
    // range split at its middle), so they are not stored.
    static std::array<Vec3, 3> axes_of(const PathBox& node);

    static bool splits(uint32_t first, uint32_t last, int depth);
    /// Nodes of the subtree over points first..last at `depth`.
    static uint32_t subtree_nodes(uint32_t first, uint32_t last, int depth);
    /// Appends the nodes over points first..last.
    static void build(PathPoints points, uint32_t first, uint32_t last, int depth, std::vector<PathBox>& out);

    double node_first_touch(uint32_t node, uint32_t first, uint32_t last, int depth, const Frustum& frustum,
                            double t_lo, double t_hi, double radius) const;
    /// The same for a node whose side is known.
    double classified_first_touch(BoxSide side, uint32_t node, uint32_t first, uint32_t last, int depth,
                                  const Frustum& frustum, double t_lo, double t_hi, double radius) const;
    /// Earliest touching time over segments first..last (and the held pose after the last point),
    /// or +infinity. `planes`: a bit per frustum plane some of these points may be beyond (a leaf
    /// box wholly inside a plane holds no point beyond it); the answer is the same as with all.
    double segments_first_touch(uint32_t first, uint32_t last, const Frustum& frustum, double t_lo, double t_hi,
                                double radius, unsigned planes = 0x3f) const;
    /// Time of the last point, or of the segments' end when a point is given.
    double end_of(uint32_t last_point) const;

    const PathBox* boxes_ = nullptr;
    const float* points_ = nullptr;
    uint32_t point_count_ = 0;
    uint32_t stride_ = 1, last_frame_ = 0;
    double record_hz_ = 120;
    double hold_end_s_ = 0;
};

/// A path that owns its points and its tree: for a path on its own, and for tests.
class PathTree : public PathView {
public:
    PathTree(std::vector<float> points, uint32_t stride, uint32_t last_frame, double record_hz,
             double hold_until_s = 0);
    PathTree(const PathTree& other);
    PathTree(PathTree&& other) noexcept = default;  // moved vectors keep their buffers: the view stays valid
    PathTree& operator=(const PathTree&) = delete;
    PathTree& operator=(PathTree&&) = delete;

private:
    std::vector<float> held_points_;
    std::vector<PathBox> held_boxes_;
};

}  // namespace mwb
