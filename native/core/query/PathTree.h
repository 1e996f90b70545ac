#pragma once
// One body's centre-of-mass path (a polyline) in an oriented-bounding-box tree of depth <= 3
// with runs of segments at the leaves. The tree keeps only its boxes: the points it tests at the
// leaves are either its own copy or borrowed from whoever drew them (the library's polylines), so
// ten thousand worlds do not hold every path twice.
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

class PathTree {
public:
    /// An oriented box in 32 bytes: single-precision centre and extents, the axes as a rotation
    /// quantized to 16 bits per component.
    struct Box {
        std::array<float, 3> center;
        std::array<int16_t, 4> rotation;  ///< w, x, y, z of a unit quaternion, times 32767
        std::array<float, 3> half_extents;
    };

    /// Builds the tree over `points` (flat (n, 3), float32), which it keeps, where point k is at
    /// time min(k·stride, last_frame) / record_hz. The last point is held from its time up to
    /// `hold_until_s` (a world that came to rest before the run's end stays where it rests).
    PathTree(std::vector<float> points, uint32_t stride, uint32_t last_frame, double record_hz,
             double hold_until_s = 0);
    /// The same over borrowed points, which must outlive the tree unchanged.
    PathTree(PathPoints points, uint32_t stride, uint32_t last_frame, double record_hz, double hold_until_s = 0);
    PathTree(PathTree&& other) noexcept = default;  // a moved vector keeps its buffer: points_ stays valid
    PathTree& operator=(PathTree&& other) noexcept = default;
    /// A copy of a tree that owns its points owns a copy of them.
    PathTree(const PathTree& other);
    PathTree& operator=(const PathTree&) = delete;

    /// Whether the path comes within `radius` of the frustum during `window` (whole path if
    /// the window is empty): whether it has a first touch. Uses the tree; the answer equals
    /// touches_brute_force exactly.
    bool touches(const Frustum& frustum, const TimeWindow& window, double radius) const;
    /// The same answer by testing every segment; for tests and benchmarks.
    bool touches_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const;
    /// First time (seconds) the path is inside the frustum, or a negative value if never.
    double first_time_inside(const Frustum& frustum) const;
    /// Earliest time (seconds) within `window` at which the path comes within `radius` of the
    /// frustum, or a negative value if it does not: touches() with the moment it happens (between
    /// samples the path is linear in time). Uses the tree, visiting earlier runs first.
    double first_touch_time(const Frustum& frustum, const TimeWindow& window, double radius) const;
    /// The same by testing every segment in order; for tests and benchmarks.
    double first_touch_time_brute_force(const Frustum& frustum, const TimeWindow& window, double radius) const;

    /// The root's oriented box, as the tree tests it; only for a path with points. Kept beside
    /// other paths' roots, it decides most queries without touching the tree.
    const Box& root_box() const { return nodes_.front(); }
    /// Whether `box` (grown by `radius`) lies wholly outside the frustum: then the path does not
    /// touch it at any time, exactly as the tree would answer.
    static bool box_outside(const Box& box, const Frustum& frustum, double radius);

    size_t point_count() const { return point_count_; }
    /// Point k as given. Tree and brute force both see exactly these points.
    Vec3 point(size_t k) const { return {points_[3 * k], points_[3 * k + 1], points_[3 * k + 2]}; }
    double time_of(size_t k) const;
    /// Time up to which the path has a pose: its last point's time, or later while that pose is held.
    double end_time_s() const { return hold_end_s_; }
    /// Bytes the tree holds: its boxes, and its points only when it owns them.
    size_t memory_bytes() const;

private:
    // A node is a Box, measured around the axes as the query rebuilds them, and
    // padded for the single-precision rounding, so every point stays inside it. Which points a
    // node covers and whether it has children follow from the point count (nodes are in
    // depth-first order, each range split at its middle), so they are not stored.
    static std::array<Vec3, 3> axes_of(const Box& node);
    static int classify(const Box& node, const Frustum& frustum, double radius);
    static bool splits(uint32_t first, uint32_t last, int depth);
    /// Nodes of the subtree over points first..last at `depth`.
    static uint32_t subtree_nodes(uint32_t first, uint32_t last, int depth);

    void build_tree(double hold_until_s);
    /// Appends the nodes over points first..last.
    void build(uint32_t first, uint32_t last, int depth);
    double node_first_touch(uint32_t node, uint32_t first, uint32_t last, int depth, const Frustum& frustum,
                            double t_lo, double t_hi, double radius) const;
    /// Earliest touching time over segments first..last (and the held pose after the last point),
    /// or +infinity.
    double segments_first_touch(uint32_t first, uint32_t last, const Frustum& frustum, double t_lo, double t_hi,
                                double radius) const;

    std::vector<float> owned_;  ///< empty when the points are borrowed
    const float* points_ = nullptr;
    uint32_t point_count_ = 0;
    std::vector<Box> nodes_;
    /// Time of the last point, or of the segments' end when a point is given.
    double end_of(uint32_t last_point) const;

    uint32_t stride_, last_frame_;
    double record_hz_;
    double hold_end_s_ = 0;
};

}  // namespace mwb
