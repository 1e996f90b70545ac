#pragma once
// Every indexed world's body paths (in OBB trees) and metrics, answering screen-box queries and
// metric rankings. Worlds are added incrementally, built in parallel outside the lock, and become
// visible to queries once complete; queries never wait for a build.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "query/GoalScore.h"
#include "query/PathTree.h"

namespace mwb {

/// What an orientation part of a goal asks of each of its bodies: that the body's own `axis`
/// (body frame) point within `within_rad` of the world direction `target` (both unit vectors).
struct OrientationTest {
    Vec3 axis{0, 0, 1};
    Vec3 target{0, 0, 1};
    double within_rad = 0;
    /// A negative part fails only when a body stays within for longer than this (seconds): a
    /// tumble through the pose is not lying in it.
    double longer_than_s = 0;
};

/// One part of a goal: a screen-space query box, or (with `orientation`, a pose part) a test of
/// the bodies' orientation over the window, which has no frustum. The index reads pose parts'
/// rotations from its RotationSource.
struct QueryBox {
    Frustum frustum;
    bool negative = false;          ///< keep worlds where no chosen body's path enters
    std::vector<uint32_t> bodies;   ///< scene body indices the box applies to
    TimeWindow window;              ///< empty: the whole path
    bool swept = false;             ///< test each body's bounding sphere, not only its origin path
    /// Position, in the same list of boxes, of the box this one must be met after; -1: any time.
    /// An ordered box counts when that box is met and its path enters this one at or after then.
    int32_t after = -1;
    /// A positive orientation part is met when every body keeps within the test at every moment of
    /// the window; a negative one when none stays within for longer than longer_than_s.
    std::optional<OrientationTest> orientation;
};

/// Where an index finds its worlds' rotations, which it does not keep (a library decodes them on
/// demand): pose parts read them. Called from the query's threads at once.
class RotationSource {
public:
    virtual ~RotationSource() = default;
    /// Per scene body, world `world_index`'s rotations at its path points for `bodies` (empty for
    /// the other bodies and for bodies the world lacks).
    virtual BodyOrientations rotations_at_path_points(uint64_t world_index, const std::vector<uint32_t>& bodies) const = 0;
};

/// A world's paths and metrics as handed to the index.
struct IndexedWorldInput {
    uint64_t world_index = 0;
    uint32_t stride = 4;        ///< recorded frames per polyline point
    uint32_t last_frame = 0;    ///< frame_count - 1
    double record_hz = 120;
    /// The run's end, seconds: a world that ended earlier (at rest) holds its final pose up to it.
    double hold_until_s = 0;
    /// Per body, flat (points, 3); the index keeps them, quantized to 16 bits per coordinate.
    std::vector<std::vector<float>> polylines;
    /// Instead of polylines: per body, points owned elsewhere (the library's polylines, drawn
    /// from the same memory), which must stay unchanged while the index lives. The index then
    /// holds only its boxes.
    std::vector<PathPoints> borrowed;
    std::vector<Quat> final_orientations;       ///< per body
    std::vector<std::string> metric_names;
    std::vector<std::vector<double>> metric_values;  ///< [metric][body]
};

struct QueryResult {
    bool superseded = false;             ///< a newer query was posted; the rest is incomplete
    std::vector<uint64_t> world_indices; ///< every indexed world, in index order
    std::vector<uint32_t> boxes_satisfied;  ///< per world
    std::vector<uint64_t> matching;      ///< worlds satisfying every box
};

enum class Combine { Sum, Max };

class PathIndex {
public:
    /// `body_radii_m`: per scene body, the radius around the object origin that bounds its shape
    /// (for swept queries).
    explicit PathIndex(std::vector<double> body_radii_m);

    /// Where pose parts find the worlds' rotations; without one, a query with a pose part throws
    /// std::invalid_argument. Safe to call while queries run (they keep the source they started
    /// with). A new source must give the same rotations for a world as the one before (the same
    /// library): answers found with it are kept.
    void set_rotation_source(std::shared_ptr<const RotationSource> source);

    /// Builds the trees of `worlds` on `threads` threads (<= 0: all), then publishes them.
    /// Worlds already indexed are ignored. Safe to call while queries run on other threads.
    void add_worlds(std::vector<IndexedWorldInput> worlds, int threads = 0);

    size_t world_count() const;
    bool contains(uint64_t world_index) const;
    size_t memory_bytes() const;

    /// Evaluates boxes and pose parts (combined by AND, ordered parts in their order, see
    /// GoalScore.h) over every indexed world, split over `threads` (<= 0: all cores); the answer is the same on any
    /// number. Throws std::invalid_argument for a bad order. If post_generation() is called with a
    /// newer number while it runs, it stops early and returns superseded. `brute_force` skips the
    /// trees (for tests and benchmarks).
    QueryResult query(const std::vector<QueryBox>& boxes, uint64_t generation = 0, bool brute_force = false,
                      int threads = 0) const;
    /// Announces that query `generation` is the one that matters now.
    void post_generation(uint64_t generation) { latest_generation_.store(generation); }

    /// Worlds (all, or `only`) sorted by `metric` combined over `bodies`. Metrics: the stored
    /// ones (see BodyMetrics.h), "orientation_to_goal_rad" (angle between each body's final
    /// orientation and `goals`, one per body in `bodies`) and "boxes_met" (how many of `boxes`
    /// each world meets, as query() counts them; every world is ranked, `bodies` unused). Each
    /// world is ranked over the bodies of `bodies` it has; a world with none of them is left out.
    /// Ties keep world-index order. Returns (world index, value) pairs.
    std::vector<std::pair<uint64_t, double>> rank(const std::string& metric, const std::vector<uint32_t>& bodies,
                                                  Combine combine, bool descending,
                                                  const std::vector<uint64_t>* only = nullptr,
                                                  const std::vector<Quat>* goals = nullptr,
                                                  const std::vector<QueryBox>* boxes = nullptr) const;

    /// How far world `world_index` gets towards the goal `boxes` (order: goal_order(boxes)).
    /// `orientations`: the world's rotations at its path points for the pose parts' bodies; without
    /// them, from the rotation source when a part needs them.
    GoalScore score(uint64_t world_index, const std::vector<QueryBox>& boxes, const std::vector<size_t>& order,
                    const BodyOrientations* orientations = nullptr) const;

    /// First time (seconds) any of `bodies` is inside `frustum` in `world_index`, or negative.
    double first_time_inside(uint64_t world_index, const std::vector<uint32_t>& bodies, const Frustum& frustum) const;

private:
    struct World {
        uint64_t world_index;
        // The clock every path of the world shares.
        uint32_t stride, last_frame;
        double record_hz, hold_until_s;
        /// Per body, in one cache line: a sphere around the path (centre, radius; negative radius:
        /// no path), the tree's root box, where its other boxes start and where its points are,
        /// so a box over many bodies rarely loads more than this.
        struct alignas(64) Root {
            std::array<float, 4> sphere;
            PathBox box;
            const uint16_t* points;  ///< a quantized block (common/QuantizedPolyline.h)
            uint32_t first_child;
            uint32_t point_count;
        };
        std::vector<Root> roots;
        std::vector<ChildBox> children;  ///< every path's boxes below its root, path after path
        std::vector<std::vector<uint16_t>> held_points;  ///< the points of paths given as polylines
        std::vector<Quat> final_orientations;
        std::vector<std::string> metric_names;
        std::vector<std::vector<double>> metric_values;

        bool has_path(uint32_t body) const { return body < roots.size() && roots[body].point_count > 0; }
        PathView path(uint32_t body) const;
        /// One view per body (empty for bodies it lacks).
        std::vector<PathView> paths() const;
    };

    static std::unique_ptr<World> build_world(IndexedWorldInput&& input);
    std::vector<const World*> snapshot() const;
    const World* find(uint64_t world_index) const;
    bool world_satisfies(const World& world, const QueryBox& box, bool brute_force) const;
    /// The rotation source, checked to be there when `boxes` has a pose part (nullptr otherwise).
    std::shared_ptr<const RotationSource> rotations_for(const std::vector<QueryBox>& boxes) const;
    /// Per world of `worlds`, whether it meets the (unordered) pose part as a query found before:
    /// 1, 0, or -1 when no query did.
    std::vector<int8_t> recalled_pose_answers(const QueryBox& part, const std::vector<const World*>& worlds) const;
    /// Keeps the answers found (those not -1) for the next query with the same part.
    void remember_pose_answers(const QueryBox& part, const std::vector<const World*>& worlds,
                               const std::vector<int8_t>& met) const;

    std::vector<double> body_radii_m_;
    mutable std::mutex mutex_;
    std::vector<std::unique_ptr<World>> worlds_;  ///< guarded by mutex_; World objects are immutable
    std::vector<uint64_t> sorted_indices_;        ///< guarded by mutex_
    std::unordered_map<uint64_t, const World*> by_index_;  ///< guarded by mutex_
    std::atomic<uint64_t> latest_generation_{0};
    std::shared_ptr<const RotationSource> rotation_source_;  ///< guarded by mutex_
    /// Pose parts' answers by part (its bytes) and world: a world's rotations never change, so a
    /// part asked again is answered without decoding them. At most kRememberedPoseParts parts.
    static constexpr size_t kRememberedPoseParts = 16;
    mutable std::mutex memo_mutex_;
    mutable std::unordered_map<std::string, std::unordered_map<uint64_t, uint8_t>> pose_answers_;  ///< guarded by memo_mutex_
};

/// The bodies the parts of `boxes` name (only its pose parts: `pose_parts_only`), ascending.
std::vector<uint32_t> named_bodies(const std::vector<QueryBox>& boxes, bool pose_parts_only = false);
/// The bodies the pose parts of `boxes` name, ascending.
std::vector<uint32_t> posed_bodies(const std::vector<QueryBox>& boxes);

}  // namespace mwb
