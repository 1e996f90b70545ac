#pragma once
// One body's centre-of-mass path (a polyline) in an oriented-bounding-box tree of depth <= 3
// with runs of segments at the leaves. A PathView queries a path whose boxes and points live
// elsewhere: the index keeps the boxes of a world's paths in one array and reads the points the
// library draws from, so ten thousand worlds do not hold every path twice. A PathTree owns both.
// Boxes below the root are stored relative to their parent in 16 bytes.
#include <array>
#include <cstdint>
#include <vector>

#include "common/QuantizedPolyline.h"
#include "query/Frustum.h"

namespace mwb {

/// A path's points owned elsewhere: a block of quantized::block_words(count) words (see
/// common/QuantizedPolyline.h).
struct PathPoints {
    const uint16_t* block = nullptr;
    uint32_t count = 0;
};

/// A time interval in seconds; the whole path when empty() (lo > hi).
struct TimeWindow {
    double lo_s = 1, hi_s = 0;
    bool empty() const { return lo_s > hi_s; }
};

/// The root's oriented box in 32 bytes: single-precision centre and extents, the axes as a
/// rotation quantized to 16 bits per component.
struct PathBox {
    std::array<float, 3> center;
    std::array<int16_t, 4> rotation;  ///< w, x, y, z of a unit quaternion, times 32767
    std::array<float, 3> half_extents;
};

/// A box below the root in 16 bytes, relative to its parent's centre c and reach r (the length of
/// its half extents), within which it lies: centre c + r·offset/32767, half extents
/// 4·r·half/65535, the axes as a rotation quantized to 8 bits per component.
struct ChildBox {
    std::array<int16_t, 3> offset;
    std::array<uint16_t, 3> half;
    std::array<int8_t, 4> rotation;  ///< w, x, y, z of a quaternion, any length
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
    /// `root` and `children`: what build_boxes made of `points`. Point k is at time
    /// min(k·stride, last_frame) / record_hz; the last point is held from its time up to
    /// `hold_until_s` (a world that came to rest before the run's end stays where it rests).
    PathView(const PathBox* root, const ChildBox* children, PathPoints points, uint32_t stride, uint32_t last_frame,
             double record_hz, double hold_until_s = 0);

    /// How many boxes below the root the tree over `point_count` points has.
    static uint32_t child_count(uint32_t point_count);
    /// Fits the tree over `points` (at least one): its root box, and appends the others to
    /// `children` in depth-first order.
    static void build_boxes(PathPoints points, PathBox& root, std::vector<ChildBox>& children);

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
    const PathBox& root_box() const { return *root_; }
    /// Where `box` (grown by `radius`) lies: wholly outside the frustum, the path does not touch
    /// it at any time, exactly as the tree would answer.
    static BoxSide box_side(const PathBox& box, const Frustum& frustum, double radius);

    size_t point_count() const { return point_count_; }
    /// Point k as stored (16 bits per coordinate). Tree and brute force both see exactly these points.
    Vec3 point(size_t k) const { return quantized::point(quantized::header(block_), block_, k); }
    double time_of(size_t k) const;
    /// Time up to which the path has a pose: its last point's time, or later while that pose is held.
    double end_time_s() const { return hold_end_s_; }

protected:
    /// Points the view at a copy of what it viewed.
    void rebind(const PathBox* root, const ChildBox* children, const uint16_t* block) {
        root_ = root;
        children_ = children;
        block_ = block;
    }

private:
    // Boxes are measured around the centre and axes as the query decodes them, and padded for
    // the rounding, so every point stays inside. Which points a node covers and whether it has
    // children follow from the point count (nodes are in depth-first order, each range split at
    // its middle), so they are not stored.
    static bool splits(uint32_t first, uint32_t last, int depth);
    /// Nodes of the subtree over points first..last at `depth`.
    static uint32_t subtree_nodes(uint32_t first, uint32_t last, int depth);
    /// Appends the boxes below a node over points first..last at `depth`, whose decoded centre
    /// and reach are given.
    static void build_children(const Vec3* points, uint32_t first, uint32_t last, int depth, const Vec3& center,
                               double reach, std::vector<ChildBox>& out);
    /// Fits a child box over points first..last within its parent's centre and reach.
    static ChildBox fit_child(const Vec3* points, uint32_t first, uint32_t last, bool leaf, const Vec3& parent_center,
                              double parent_reach);

    /// Node `node` (1 and up: children_[node - 1]) over points first..last, below a parent of
    /// this centre and reach that crosses `planes` (its points lie inside the others).
    double node_first_touch(uint32_t node, uint32_t first, uint32_t last, int depth, const Vec3& parent_center,
                            double parent_reach, unsigned planes, const Frustum& frustum, double t_lo, double t_hi,
                            double radius) const;
    /// The same for a node whose side, centre and half extents are known.
    double classified_first_touch(BoxSide side, uint32_t node, uint32_t first, uint32_t last, int depth,
                                  const Vec3& center, const Vec3& half, const Frustum& frustum, double t_lo,
                                  double t_hi, double radius) const;
    /// Earliest touching time over segments first..last (and the held pose after the last point),
    /// or +infinity. `planes`: a bit per frustum plane some of these points may be beyond (a leaf
    /// box wholly inside a plane holds no point beyond it); the answer is the same as with all.
    double segments_first_touch(uint32_t first, uint32_t last, const Frustum& frustum, double t_lo, double t_hi,
                                double radius, unsigned planes = 0x3f) const;
    /// Time of the last point, or of the segments' end when a point is given.
    double end_of(uint32_t last_point) const;

    const PathBox* root_ = nullptr;
    const ChildBox* children_ = nullptr;
    // The block's header is read where points are (a query the boxes decide never loads it).
    const uint16_t* block_ = nullptr;
    uint32_t point_count_ = 0;
    uint32_t stride_ = 1, last_frame_ = 0;
    double record_hz_ = 120;
    double hold_end_s_ = 0;
};

/// A path that owns its points and its tree: for a path on its own, and for tests.
class PathTree : public PathView {
public:
    /// Over `points` (flat (n, 3)), which it keeps quantized to 16 bits per coordinate.
    PathTree(const std::vector<float>& points, uint32_t stride, uint32_t last_frame, double record_hz,
             double hold_until_s = 0);
    PathTree(const PathTree& other);
    PathTree(PathTree&& other) noexcept;
    PathTree& operator=(const PathTree&) = delete;
    PathTree& operator=(PathTree&&) = delete;

private:
    std::vector<uint16_t> held_block_;
    PathBox held_root_{};
    std::vector<ChildBox> held_children_;
};

}  // namespace mwb
