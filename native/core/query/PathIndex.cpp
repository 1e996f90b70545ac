#include "query/PathIndex.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>

namespace mwb {
namespace {

// A sphere around a whole path, for a cheap first rejection before the tree: the one around its
// root box, which holds every point.
std::array<float, 4> bounding_sphere(const PathBox& root) {
    const double r = norm(Vec3{root.half_extents[0], root.half_extents[1], root.half_extents[2]});
    return {root.center[0], root.center[1], root.center[2], static_cast<float>(r * (1 + 1e-6) + 1e-6)};
}

bool sphere_outside(const Frustum& f, const std::array<float, 4>& s, double radius) {
    const Vec3 c{s[0], s[1], s[2]};
    for (const Plane& p : f.planes)
        if (p.distance(c) < -(s[3] + radius)) return true;
    return false;
}

}  // namespace

PathIndex::PathIndex(std::vector<double> body_radii_m) : body_radii_m_(std::move(body_radii_m)) {}

std::vector<uint32_t> named_bodies(const std::vector<QueryBox>& boxes, bool pose_parts_only) {
    std::vector<uint32_t> bodies;
    for (const QueryBox& box : boxes)
        if (box.orientation || !pose_parts_only) bodies.insert(bodies.end(), box.bodies.begin(), box.bodies.end());
    std::sort(bodies.begin(), bodies.end());
    bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
    return bodies;
}

std::vector<uint32_t> posed_bodies(const std::vector<QueryBox>& boxes) { return named_bodies(boxes, true); }

void PathIndex::set_rotation_source(std::shared_ptr<const RotationSource> source) {
    std::lock_guard<std::mutex> lock(mutex_);
    rotation_source_ = std::move(source);
}

std::shared_ptr<const RotationSource> PathIndex::rotations_for(const std::vector<QueryBox>& boxes) const {
    if (std::none_of(boxes.begin(), boxes.end(), [](const QueryBox& b) { return b.orientation.has_value(); }))
        return nullptr;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!rotation_source_)
        throw std::invalid_argument("the index has no rotations for pose parts: index the worlds from their library");
    return rotation_source_;
}

PathView PathIndex::World::path(uint32_t body) const {
    if (!has_path(body)) return {};
    const Root& root = roots[body];
    return PathView(&root.box, children.data() + root.first_child, {root.points, root.point_count}, stride,
                    last_frame, record_hz, hold_until_s);
}

std::vector<PathView> PathIndex::World::paths() const {
    std::vector<PathView> out(roots.size());
    for (uint32_t body = 0; body < roots.size(); ++body) out[body] = path(body);
    return out;
}

std::unique_ptr<PathIndex::World> PathIndex::build_world(IndexedWorldInput&& input) {
    auto world = std::make_unique<World>();
    world->world_index = input.world_index;
    world->stride = std::max<uint32_t>(1, input.stride);
    world->last_frame = input.last_frame;
    world->record_hz = input.record_hz;
    world->hold_until_s = input.hold_until_s;
    const bool borrowed = !input.borrowed.empty();
    const size_t count = borrowed ? input.borrowed.size() : input.polylines.size();
    std::vector<PathPoints> points(count);
    if (borrowed) {
        points = input.borrowed;
    } else {
        world->held_points.resize(count);
        for (size_t b = 0; b < count; ++b) {
            world->held_points[b] = quantized::encode_flat(input.polylines[b]);
            points[b] = {world->held_points[b].data(), static_cast<uint32_t>(input.polylines[b].size() / 3)};
        }
    }
    uint32_t child_total = 0;
    for (const PathPoints& p : points) child_total += PathView::child_count(p.count);
    world->children.reserve(child_total);
    world->roots.resize(count);
    for (size_t b = 0; b < count; ++b) {
        World::Root& root = world->roots[b];
        root.first_child = static_cast<uint32_t>(world->children.size());
        root.points = points[b].block;
        root.point_count = points[b].count;
        root.box = PathBox{};
        if (points[b].count > 0) PathView::build_boxes(points[b], root.box, world->children);
        root.sphere = points[b].count > 0 ? bounding_sphere(root.box) : std::array<float, 4>{0, 0, 0, -1};
    }
    world->final_orientations = std::move(input.final_orientations);
    world->metric_names = std::move(input.metric_names);
    world->metric_values = std::move(input.metric_values);
    return world;
}

void PathIndex::add_worlds(std::vector<IndexedWorldInput> worlds, int threads) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        worlds.erase(std::remove_if(worlds.begin(), worlds.end(),
                                    [&](const IndexedWorldInput& w) {
                                        return std::binary_search(sorted_indices_.begin(), sorted_indices_.end(), w.world_index);
                                    }),
                     worlds.end());
    }
    // A world may have fewer paths than the scene has bodies: bodies added after it was made.
    for (const IndexedWorldInput& w : worlds) {
        const size_t paths = std::max(w.polylines.size(), w.borrowed.size());
        if (!w.polylines.empty() && !w.borrowed.empty())
            throw std::invalid_argument("world " + std::to_string(w.world_index) +
                                        " has both its own and borrowed paths");
        if (paths > body_radii_m_.size())
            throw std::invalid_argument("world " + std::to_string(w.world_index) + " has " + std::to_string(paths) +
                                        " paths, the index " + std::to_string(body_radii_m_.size()) + " bodies");
    }
    std::vector<std::unique_ptr<World>> built(worlds.size());
    const int thread_count = threads > 0 ? threads : omp_get_max_threads();
    const auto count = static_cast<long long>(worlds.size());
#pragma omp parallel for num_threads(thread_count) schedule(dynamic, 4)
    for (long long k = 0; k < count; ++k) built[static_cast<size_t>(k)] = build_world(std::move(worlds[static_cast<size_t>(k)]));
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& world : built) {
        if (std::binary_search(sorted_indices_.begin(), sorted_indices_.end(), world->world_index)) continue;
        sorted_indices_.insert(std::upper_bound(sorted_indices_.begin(), sorted_indices_.end(), world->world_index),
                               world->world_index);
        by_index_[world->world_index] = world.get();
        worlds_.push_back(std::move(world));
    }
}

size_t PathIndex::world_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return worlds_.size();
}

bool PathIndex::contains(uint64_t world_index) const {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::binary_search(sorted_indices_.begin(), sorted_indices_.end(), world_index);
}

size_t PathIndex::memory_bytes() const {
    std::lock_guard<std::mutex> lock(mutex_);
    size_t bytes = sizeof(*this);
    for (const auto& w : worlds_) {
        bytes += sizeof(World) + w->roots.capacity() * sizeof(World::Root) + w->children.capacity() * sizeof(ChildBox) +
                 w->final_orientations.capacity() * sizeof(Quat);
        for (const auto& p : w->held_points) bytes += p.capacity() * sizeof(uint16_t);
        for (const auto& m : w->metric_values) bytes += m.capacity() * sizeof(double);
    }
    return bytes;
}

std::vector<const PathIndex::World*> PathIndex::snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<const World*> out;
    out.reserve(worlds_.size());
    for (const auto& w : worlds_) out.push_back(w.get());
    std::sort(out.begin(), out.end(), [](const World* a, const World* b) { return a->world_index < b->world_index; });
    return out;
}

bool PathIndex::world_satisfies(const World& world, const QueryBox& box, bool brute_force) const {
    bool entered = false;
    for (uint32_t body : box.bodies) {
        if (body >= body_radii_m_.size()) throw std::out_of_range("query box names body " + std::to_string(body));
        // A body the world does not have (no path) never enters a box.
        if (!world.has_path(body)) continue;
        const World::Root& root = world.roots[body];
        const double radius = box.swept ? body_radii_m_[body] : 0.0;
        BoxSide root_side;
        if (!brute_force) {
            if (sphere_outside(box.frustum, root.sphere, radius)) continue;
            // The tree's first boxes load while the root box is tested.
            const char* tree = reinterpret_cast<const char*>(world.children.data() + root.first_child);
            for (int line = 0; line < 4; ++line) __builtin_prefetch(tree + 64 * line);
            root_side = PathView::box_side(root.box, box.frustum, radius);
            if (root_side.side < 0) continue;
        }
        const PathView path = world.path(body);
        if (brute_force ? path.touches_brute_force(box.frustum, box.window, radius)
                        : path.touches(box.frustum, box.window, radius, &root_side)) {
            entered = true;
            break;
        }
    }
    return entered != box.negative;
}

namespace {

// What decides a pose part's answer for a world, as bytes: two parts with the same key are met
// by the same worlds (when neither is ordered).
std::string pose_key(const QueryBox& part) {
    const OrientationTest& test = *part.orientation;
    const double numbers[] = {test.axis[0],   test.axis[1],   test.axis[2],        test.target[0],
                              test.target[1], test.target[2], test.within_rad,     test.longer_than_s,
                              part.window.lo_s, part.window.hi_s, part.negative ? 1.0 : 0.0};
    std::string key(reinterpret_cast<const char*>(numbers), sizeof numbers);
    key.append(reinterpret_cast<const char*>(part.bodies.data()), part.bodies.size() * sizeof(uint32_t));
    return key;
}

}  // namespace

QueryResult PathIndex::query(const std::vector<QueryBox>& boxes, uint64_t generation, bool brute_force,
                             int threads) const {
    const std::vector<const World*> worlds = snapshot();
    const std::shared_ptr<const RotationSource> rotations = rotations_for(boxes);
    const std::vector<uint32_t> posed = posed_bodies(boxes);
    // Ordered parts are scored world by world along the order; otherwise boxes go through the
    // trees, and each pose part (which has no tree) on its own, its answers kept for the next
    // query: dragging a box beside a pose part does not decode the rotations again.
    const bool ordered = std::any_of(boxes.begin(), boxes.end(), [](const QueryBox& b) { return b.after >= 0; });
    const std::vector<size_t> order = goal_order(boxes);
    for (const QueryBox& box : boxes) {
        for (uint32_t body : box.bodies)
            if (body >= body_radii_m_.size()) throw std::out_of_range("query box names body " + std::to_string(body));
    }
    // Per pose part (unordered goals only), per world: met (1), not (0) or not known yet (-1); and
    // the part as a goal of its own, scored alone.
    std::vector<std::vector<int8_t>> pose_met(boxes.size());
    std::vector<std::vector<QueryBox>> pose_alone(boxes.size());
    const std::vector<size_t> alone_order{0};
    if (!ordered)
        for (size_t p = 0; p < boxes.size(); ++p)
            if (boxes[p].orientation) {
                pose_met[p] = recalled_pose_answers(boxes[p], worlds);
                pose_alone[p] = {boxes[p]};
            }
    // Each world's count is written to its own slot and the answer is assembled in world order,
    // so the result does not depend on the thread count.
    std::vector<uint32_t> satisfied(worlds.size(), 0);
    std::atomic<bool> superseded{false};
    std::exception_ptr error;
    std::mutex error_mutex;
    const int thread_count = threads > 0 ? threads : omp_get_max_threads();
    const auto count = static_cast<std::ptrdiff_t>(worlds.size());
#pragma omp parallel for num_threads(thread_count) schedule(dynamic, 64)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
        // Checking every 64 worlds keeps the atomic off the hot path yet stops within ~0.1 ms.
        if (k % 64 == 0 && generation != 0 && latest_generation_.load(std::memory_order_relaxed) > generation)
            superseded.store(true, std::memory_order_relaxed);
        if (superseded.load(std::memory_order_relaxed)) continue;
        const auto slot = static_cast<size_t>(k);
        const World& world = *worlds[slot];
        // The query waits on memory, not arithmetic: start loading the next worlds' roots (and the
        // world after's object, which says where its roots are) while this one is tested.
        if (k + 2 < count) __builtin_prefetch(worlds[slot + 2]);
        if (k + 1 < count) {
            const World& next = *worlds[slot + 1];
            const char* roots = reinterpret_cast<const char*>(next.roots.data());
            for (int line = 0; line < 4; ++line) __builtin_prefetch(roots + 64 * line);
        }
        uint32_t met = 0;
        // A world whose rotations cannot be read (a damaged track) stops the query with the
        // reason, once the loop is done.
        try {
            if (ordered) {
                BodyOrientations orientations;
                if (rotations) orientations = rotations->rotations_at_path_points(world.world_index, posed);
                met = score_goal(world.paths(), body_radii_m_, boxes, order, false, &orientations).boxes_met;
            } else
                for (size_t p = 0; p < boxes.size(); ++p) {
                    if (!boxes[p].orientation) {
                        met += world_satisfies(world, boxes[p], brute_force);
                        continue;
                    }
                    int8_t& known = pose_met[p][slot];
                    if (known < 0) {
                        const BodyOrientations orientations =
                            rotations->rotations_at_path_points(world.world_index, boxes[p].bodies);
                        known = score_goal(world.paths(), body_radii_m_, pose_alone[p], alone_order, false, &orientations).boxes_met;
                    }
                    met += static_cast<uint32_t>(known);
                }
        } catch (...) {
            std::lock_guard<std::mutex> lock(error_mutex);
            if (!error) error = std::current_exception();
        }
        satisfied[slot] = met;
    }
    if (error) std::rethrow_exception(error);
    for (size_t p = 0; p < boxes.size(); ++p)
        if (!pose_met[p].empty()) remember_pose_answers(boxes[p], worlds, pose_met[p]);
    QueryResult result;
    if (superseded.load()) {
        result.superseded = true;
        return result;
    }
    result.world_indices.reserve(worlds.size());
    result.boxes_satisfied = std::move(satisfied);
    for (size_t k = 0; k < worlds.size(); ++k) {
        result.world_indices.push_back(worlds[k]->world_index);
        if (result.boxes_satisfied[k] == boxes.size()) result.matching.push_back(worlds[k]->world_index);
    }
    return result;
}

std::vector<int8_t> PathIndex::recalled_pose_answers(const QueryBox& part, const std::vector<const World*>& worlds) const {
    std::vector<int8_t> met(worlds.size(), -1);
    std::lock_guard<std::mutex> lock(memo_mutex_);
    const auto it = pose_answers_.find(pose_key(part));
    if (it == pose_answers_.end()) return met;
    for (size_t k = 0; k < worlds.size(); ++k) {
        const auto known = it->second.find(worlds[k]->world_index);
        if (known != it->second.end()) met[k] = static_cast<int8_t>(known->second);
    }
    return met;
}

void PathIndex::remember_pose_answers(const QueryBox& part, const std::vector<const World*>& worlds,
                                      const std::vector<int8_t>& met) const {
    std::lock_guard<std::mutex> lock(memo_mutex_);
    const std::string key = pose_key(part);
    auto it = pose_answers_.find(key);
    if (it == pose_answers_.end()) {
        // The parts of the goal being edited and a few before: an animator tries tolerances.
        if (pose_answers_.size() >= kRememberedPoseParts) pose_answers_.clear();
        it = pose_answers_.emplace(key, std::unordered_map<uint64_t, uint8_t>{}).first;
    }
    for (size_t k = 0; k < worlds.size(); ++k)
        if (met[k] >= 0) it->second[worlds[k]->world_index] = static_cast<uint8_t>(met[k]);
}

std::vector<std::pair<uint64_t, double>> PathIndex::rank(const std::string& metric, const std::vector<uint32_t>& bodies,
                                                         Combine combine, bool descending,
                                                         const std::vector<uint64_t>* only,
                                                         const std::vector<Quat>* goals,
                                                         const std::vector<QueryBox>* boxes) const {
    // Ties keep world order, so a ranking is reproducible.
    auto sorted = [descending](std::vector<std::pair<uint64_t, double>> ranked) {
        std::stable_sort(ranked.begin(), ranked.end(), [descending](const auto& a, const auto& b) {
            return descending ? a.second > b.second : a.second < b.second;
        });
        return ranked;
    };
    if (metric == "boxes_met") {
        if (!boxes) throw std::invalid_argument("boxes_met ranks by boxes: give the boxes");
        const QueryResult met = query(*boxes);
        std::vector<std::pair<uint64_t, double>> ranked;
        for (size_t w = 0; w < met.world_indices.size(); ++w)
            if (!only || std::binary_search(only->begin(), only->end(), met.world_indices[w]))
                ranked.emplace_back(met.world_indices[w], static_cast<double>(met.boxes_satisfied[w]));
        return sorted(std::move(ranked));
    }
    const bool to_goal = metric == "orientation_to_goal_rad";
    if (to_goal && (!goals || goals->size() != bodies.size()))
        throw std::invalid_argument("orientation_to_goal_rad needs one goal orientation per body");
    for (uint32_t body : bodies)
        if (body >= body_radii_m_.size()) throw std::out_of_range("ranking names body " + std::to_string(body));
    std::vector<const World*> worlds;
    for (const World* world : snapshot())
        if (!only || std::binary_search(only->begin(), only->end(), world->world_index)) worlds.push_back(world);
    // Where each world keeps the metric's values (found once, before the parallel loop).
    std::vector<size_t> metric_slot(worlds.size(), 0);
    if (!to_goal)
        for (size_t w = 0; w < worlds.size(); ++w) {
            const std::vector<std::string>& names = worlds[w]->metric_names;
            const auto it = std::find(names.begin(), names.end(), metric);
            if (it == names.end()) throw std::invalid_argument("unknown metric '" + metric + "'");
            metric_slot[w] = static_cast<size_t>(it - names.begin());
        }
    // One slot per world, filled on all cores, then gathered in world order: the same ranking on
    // any number of threads.
    std::vector<double> combined(worlds.size(), 0.0);
    std::vector<uint8_t> ranked_here(worlds.size(), 0);
    const auto count = static_cast<std::ptrdiff_t>(worlds.size());
#pragma omp parallel for schedule(dynamic, 64)
    for (std::ptrdiff_t w = 0; w < count; ++w) {
        const World& world = *worlds[static_cast<size_t>(w)];
        const std::vector<double>* values = to_goal ? nullptr : &world.metric_values[metric_slot[static_cast<size_t>(w)]];
        double value = combine == Combine::Sum ? 0.0 : -std::numeric_limits<double>::infinity();
        size_t counted = 0;
        for (size_t k = 0; k < bodies.size(); ++k) {
            // A world is ranked over the bodies it has (bodies can be added and removed).
            if (!world.has_path(bodies[k])) continue;
            const double v = to_goal ? quat_angle_between(world.final_orientations[bodies[k]], (*goals)[k])
                                     : (*values)[bodies[k]];
            value = combine == Combine::Sum ? value + v : std::max(value, v);
            ++counted;
        }
        combined[static_cast<size_t>(w)] = value;
        ranked_here[static_cast<size_t>(w)] = counted > 0 || bodies.empty();
    }
    std::vector<std::pair<uint64_t, double>> ranked;
    for (size_t w = 0; w < worlds.size(); ++w)
        if (ranked_here[w]) ranked.emplace_back(worlds[w]->world_index, combined[w]);
    return sorted(std::move(ranked));
}

const PathIndex::World* PathIndex::find(uint64_t world_index) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = by_index_.find(world_index);
    return it == by_index_.end() ? nullptr : it->second;
}

GoalScore PathIndex::score(uint64_t world_index, const std::vector<QueryBox>& boxes,
                           const std::vector<size_t>& order, const BodyOrientations* orientations) const {
    const World* world = find(world_index);
    if (!world) throw std::out_of_range("world " + std::to_string(world_index) + " is not indexed");
    BodyOrientations decoded;
    if (!orientations)
        if (const std::shared_ptr<const RotationSource> rotations = rotations_for(boxes)) {
            decoded = rotations->rotations_at_path_points(world_index, posed_bodies(boxes));
            orientations = &decoded;
        }
    return score_goal(world->paths(), body_radii_m_, boxes, order, true, orientations);
}

double PathIndex::first_time_inside(uint64_t world_index, const std::vector<uint32_t>& bodies, const Frustum& frustum) const {
    for (const World* world : snapshot()) {
        if (world->world_index != world_index) continue;
        double first = -1;
        for (uint32_t body : bodies) {
            if (body >= body_radii_m_.size()) throw std::out_of_range("body " + std::to_string(body) + " is not in the scene");
            if (!world->has_path(body)) continue;
            const double t = world->path(body).first_time_inside(frustum);
            if (t >= 0 && (first < 0 || t < first)) first = t;
        }
        return first;
    }
    throw std::out_of_range("world " + std::to_string(world_index) + " is not indexed");
}

}  // namespace mwb
