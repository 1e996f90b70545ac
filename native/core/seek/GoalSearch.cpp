#include "seek/GoalSearch.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include "common/PortableMath.h"
#include "geometry/ShapeBounds.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "refine/LineageCache.h"
#include "refine/StoredWorldRefinement.h"
#include "scene/SceneJson.h"
#include "seek/GoalJson.h"
#include "seek/WorldIndexing.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

// Polylines at 30 Hz: the browser's own rate, so the search sees worlds as the user does.
constexpr double kPolylineHz = 30;
// Branch points just before a box's window opens, seconds.
constexpr double kBeforeWindow[] = {0.1, 0.25, 0.5, 1.0, 2.0};
// Spacing of the fallback branch points when nothing collided in the span, seconds.
constexpr double kGridSpacing = 0.5;
// Negative boxes entered by many bodies: the earliest few are refined.
constexpr size_t kMaxFailingBodies = 8;
// A refinement helps when a child meets another box or comes this much closer to the next one;
// smaller gains would keep the search polishing one world instead of backing up.
constexpr double kMeaningfulGain = 0.02;
// Beam worlds from one sampled world's family: one keeps the search from spending everything on
// the descendants of a single lucky start (on the quick-start goal, from the same 8 worlds and
// 6 seeds, the most it took fell from 1,000 worlds to 424, and the staircase got as far).
constexpr uint32_t kBeamPerFamily = 1;

struct Branch {
    uint64_t frame = 0;
    std::vector<uint32_t> bodies;
    bool operator<(const Branch& o) const { return std::tie(frame, bodies) < std::tie(o.frame, o.bodies); }
    bool operator==(const Branch& o) const { return frame == o.frame && bodies == o.bodies; }
};

class GoalSearch {
public:
    GoalSearch(const std::string& path, const SeekRequest& request, const SeekListener& on_status,
               SamplingProgress* progress)
        : request_(request),
          on_status_(on_status),
          progress_(progress ? progress : &own_progress_),
          reader_(path, ReaderOptions{false, kPolylineHz}),
          writer_(path, reader_.header()),
          scene_(scene_from_json(reader_.scene_json())),
          index_(body_radii(scene_)),
          cache_(request.cache_bytes),
          random_(request.seed ^ 0x5eecULL),
          start_(std::chrono::steady_clock::now()) {
        check_request();
        order_ = goal_order(request_.boxes);
    }

    SeekOutcome run() {
        if (reader_.worlds().empty()) sample_batch();
        take_new_worlds();
        report();
        while (!finished()) {
            std::vector<uint64_t> beam = choose_beam();
            if (beam.empty()) {
                // Every good world's branch points are spent: start over from new sampled worlds.
                sample_batch();
                take_new_worlds();
                report();
                continue;
            }
            for (uint64_t world : beam) {
                if (finished()) break;
                refine_once(world);
                report();
            }
        }
        return outcome();
    }

private:
    static std::vector<double> body_radii(const Scene& scene) {
        std::vector<double> radii;
        for (const Body& b : scene.bodies) radii.push_back(body_bounding_radius(b));
        return radii;
    }

    void check_request() const {
        if (request_.boxes.empty()) throw GoalError("the goal has no boxes: draw at least one box");
        if (request_.want == 0) throw GoalError("the number of worlds to find must be at least 1");
        if (request_.budget_worlds == 0) throw GoalError("the budget must allow at least one world");
        if (request_.budget_s < 0) throw GoalError("the time budget must not be negative");
        for (size_t k = 0; k < request_.boxes.size(); ++k)
            for (uint32_t body : request_.boxes[k].bodies)
                if (body >= scene_.bodies.size())
                    throw GoalError("box " + std::to_string(k + 1) + " names body " + std::to_string(body) +
                                    ", which the library's scene does not have");
    }

    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

    bool out_of_budget() const {
        return made_ >= request_.budget_worlds || (request_.budget_s > 0 && elapsed() >= request_.budget_s);
    }

    bool finished() const { return found_.size() >= request_.want || out_of_budget() || progress_->cancel.load(); }

    // --- worlds in, scored ---------------------------------------------------------------------

    void take_new_worlds() {
        reader_.poll();
        std::vector<IndexedWorldInput> inputs;
        std::vector<uint64_t> fresh;
        for (size_t k = 0; k < reader_.worlds().size(); ++k) {
            const StoredWorld& w = reader_.worlds()[k];
            if (position_.count(w.world_index)) continue;
            position_[w.world_index] = k;
            inputs.push_back(indexed_world_input(reader_, w));
            fresh.push_back(w.world_index);
        }
        index_.add_worlds(std::move(inputs), request_.threads);
        // In index order, not file order (which depends on which thread finished first): which of
        // two equal worlds counts is then the same on any thread count.
        std::sort(fresh.begin(), fresh.end());
        for (uint64_t w : fresh) {
            GoalScore score = index_.score(w, request_.boxes, order_);
            if (score.first_unmet < 0) found_.insert(w);
            // A world that gets as far as one already scored (to a thousandth of a box) is, for
            // the goal, the same world: refining both would repeat work.
            else if (!seen_values_.insert(std::llround(score.value() * 1000)).second) spent_.insert(w);
            const auto key = std::make_pair(-score.value(), w);
            ranking_.insert(key);
            scores_.emplace(w, std::move(score));
        }
    }

    const StoredWorld& stored(uint64_t world) const { return reader_.worlds()[position_.at(world)]; }

    uint64_t best_world() const { return ranking_.empty() ? 0 : ranking_.begin()->second; }

    // The sampled world `world` descends from (itself if sampled).
    uint64_t family_of(uint64_t world) const {
        const StoredWorld& w = stored(world);
        return w.lineage.empty() ? w.world_index : w.root_world;
    }

    // The best worlds not yet met or spent, best first (ties: lower index), at most
    // kBeamPerFamily from one sampled world's family, then the best of the rest if the beam is
    // not full.
    std::vector<uint64_t> choose_beam() const {
        std::vector<uint64_t> beam;
        std::map<uint64_t, uint32_t> per_family;
        for (const auto& [negative_value, world] : ranking_) {
            if (beam.size() >= request_.beam_width) break;
            if (found_.count(world) || spent_.count(world)) continue;
            if (per_family[family_of(world)]++ >= kBeamPerFamily) continue;
            beam.push_back(world);
        }
        for (const auto& [negative_value, world] : ranking_) {
            if (beam.size() >= request_.beam_width) break;
            if (found_.count(world) || spent_.count(world)) continue;
            if (std::find(beam.begin(), beam.end(), world) == beam.end()) beam.push_back(world);
        }
        return beam;
    }

    // --- where to branch -------------------------------------------------------------------------

    bool simulated(uint32_t body) const { return body < scene_.bodies.size() && body_role(scene_.bodies[body]) == BodyRole::Simulated; }

    std::vector<Branch> branch_points(uint64_t world) const {
        const StoredWorld& w = stored(world);
        const GoalScore& score = scores_.at(world);
        const QueryBox& box = request_.boxes[static_cast<size_t>(score.first_unmet)];
        const double hz = w.record_hz;
        const double world_end = (w.first_frame + w.frame_count - 1) / hz;
        // Keep what the boxes before it in the order achieved, all but the last: branch after the
        // box two before it was met. Branching only after the box it follows leaves too little
        // to change when the world got there already stopping (a body coming to rest on the step
        // it just reached); later points are still tried first, so the last box is kept when it can be.
        double lower = 0.0;
        if (box.after >= 0) {
            const int32_t earlier = request_.boxes[static_cast<size_t>(box.after)].after;
            lower = earlier >= 0 ? score.met_time_s[static_cast<size_t>(earlier)] : 0.0;
        }
        double upper = std::min(score.failure_time_s, world_end);
        if (!(upper > lower)) upper = world_end;
        std::vector<uint32_t> failing;
        for (uint32_t b : score.failing_bodies)
            if (simulated(b) && failing.size() < kMaxFailingBodies) failing.push_back(b);
        if (failing.empty())
            for (uint32_t b : box.bodies)
                if (simulated(b) && failing.size() < kMaxFailingBodies) failing.push_back(b);
        if (failing.empty()) return {};
        // Branching after the bodies came to rest changes nothing (unless something hits them).
        const double rest = rest_time(w, failing);
        if (rest + 1 / hz < upper) upper = rest + 1 / hz;
        if (!(upper > lower)) upper = world_end;

        std::set<Branch> points;
        auto add = [&](double t, std::vector<uint32_t> bodies) {
            if (!(t >= lower && t < upper)) return;
            std::sort(bodies.begin(), bodies.end());
            bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
            points.insert({static_cast<uint64_t>(std::floor(t * hz)), std::move(bodies)});
        };
        // The bodies that missed, with everything jointed to them: an arm's impact turns the body.
        const std::set<uint32_t> failing_set = jointed_with(failing);
        // Collisions of those bodies, and of the simulated bodies that hit them.
        std::set<uint32_t> hitters;
        for (const ContactEvent& c : w.contacts) {
            if (c.body < 0 || !failing_set.count(static_cast<uint32_t>(c.body))) continue;
            add(c.time_s, failing);
            if (c.other >= 0 && simulated(static_cast<uint32_t>(c.other)) && !failing_set.count(static_cast<uint32_t>(c.other)) &&
                c.time_s >= lower && c.time_s < upper)
                hitters.insert(static_cast<uint32_t>(c.other));
        }
        for (const ContactEvent& c : w.contacts) {
            if (c.body < 0 || !hitters.count(static_cast<uint32_t>(c.body))) continue;
            std::vector<uint32_t> bodies = failing;
            bodies.push_back(static_cast<uint32_t>(c.body));
            add(c.time_s, bodies);
        }
        // Just before the box's window opens.
        const double opens = box.window.empty() ? upper : std::max(box.window.lo_s, score.window_start_s);
        for (double before : kBeforeWindow) add(opens - before, failing);
        if (points.size() < 4)
            for (double t = lower; t < upper; t += kGridSpacing) add(t, failing);
        return {points.begin(), points.end()};
    }

    // `bodies` and every body joined to them through enabled constraints, transitively.
    std::set<uint32_t> jointed_with(const std::vector<uint32_t>& bodies) const {
        std::set<uint32_t> group(bodies.begin(), bodies.end());
        for (bool grew = true; grew;) {
            grew = false;
            for (const Constraint& c : scene_.constraints) {
                if (!c.enabled) continue;
                const int a = scene_.body_index(c.body_a), b = scene_.body_index(c.body_b);
                if (a < 0 || b < 0 || !simulated(static_cast<uint32_t>(a)) || !simulated(static_cast<uint32_t>(b))) continue;
                const bool has_a = group.count(static_cast<uint32_t>(a)) > 0, has_b = group.count(static_cast<uint32_t>(b)) > 0;
                if (has_a != has_b) {
                    group.insert(static_cast<uint32_t>(has_a ? b : a));
                    grew = true;
                }
            }
        }
        return group;
    }

    // When the last of `bodies` came to rest for good (the world's end if one never did).
    static double rest_time(const StoredWorld& w, const std::vector<uint32_t>& bodies) {
        const double world_end = (w.first_frame + w.frame_count - 1) / w.record_hz;
        for (const MetricValues& m : w.metrics) {
            if (m.name != "time_to_rest_s") continue;
            double last = 0;
            for (uint32_t b : bodies) last = std::max(last, b < m.per_body.size() ? m.per_body[b] : world_end);
            return last;
        }
        return world_end;
    }

    // Later branch points first: they keep more of what the world got right. Each failed
    // refinement of a world moves the preferred point back (1, 2, 4, ... points earlier).
    bool choose_branch(uint64_t world, Branch& chosen) {
        std::vector<Branch> points = branch_points(world);
        std::vector<size_t> open;
        for (size_t k = 0; k < points.size(); ++k)
            if (!tried_.count({world, points[k]})) open.push_back(k);
        if (open.empty()) return false;
        const uint32_t failures = std::min<uint32_t>(failures_[world], 20);
        const double target = static_cast<double>(points.size() - 1) - static_cast<double>((1u << failures) - 1);
        std::vector<double> weights;
        double total = 0;
        for (size_t k : open) {
            weights.push_back(portable::pow(0.5, std::fabs(static_cast<double>(k) - std::max(0.0, target))));
            total += weights.back();
        }
        double pick = random_.uniform01() * total;
        size_t choice = open.back();
        for (size_t i = 0; i < open.size(); ++i) {
            if (pick < weights[i]) {
                choice = open[i];
                break;
            }
            pick -= weights[i];
        }
        chosen = points[choice];
        tried_.insert({world, chosen});
        return true;
    }

    // --- making worlds ---------------------------------------------------------------------------

    void refine_once(uint64_t world) {
        Branch branch;
        if (!choose_branch(world, branch)) {
            spent_.insert(world);
            return;
        }
        const StoredWorld& parent = stored(world);
        RefineRequest refine;
        refine.parent_world = world;
        refine.bodies = branch.bodies;
        // The middle of the frame: it snaps down to exactly this frame.
        refine.branch_time_s = (static_cast<double>(branch.frame) + 0.5) / parent.record_hz;
        refine.count = std::min<uint64_t>(request_.children_per_branch, request_.budget_worlds - made_);
        refine.threads = request_.threads;
        RefineOutcome outcome;
        try {
            outcome = refine_stored_world(reader_, refine, writer_, {}, progress_, &cache_);
        } catch (const WorldNotReproduced&) {
            throw;  // another build's library: no branch point of it can be refined here
        } catch (const RefineError&) {
            return;  // this branch point does not fit (e.g. a body that is not simulated there); others may
        }
        made_ += refine.count;
        ++refinements_;
        take_new_worlds();
        const double parent_value = scores_.at(world).value();
        const uint32_t parent_failures = failures_[world];
        double best_child = -1;
        for (uint64_t child = outcome.first_child; child < outcome.first_child + refine.count; ++child) {
            if (!scores_.count(child)) continue;
            const double value = scores_.at(child).value();
            best_child = std::max(best_child, value);
            // A child no better than its parent failed where the parent did: it starts backing
            // up from there instead of trying the same late branch points again.
            failures_[child] = value > parent_value + kMeaningfulGain ? 0 : parent_failures + 1;
        }
        if (best_child > parent_value + kMeaningfulGain) failures_[world] = 0;
        else ++failures_[world];
        note_progress();
    }

    // Fresh sampled worlds when refinement has stopped getting anywhere: the search never does
    // worse than sampling, and a new start may succeed where every branch of the old ones failed.
    void note_progress() {
        const double best = ranking_.empty() ? 0.0 : -ranking_.begin()->first;
        if (best > best_value_ + kMeaningfulGain) {
            best_value_ = best;
            made_at_progress_ = made_;
        } else if (made_ - made_at_progress_ >= stagnation_worlds()) {
            sample_batch();
            take_new_worlds();
            made_at_progress_ = made_;
        }
    }

    uint64_t stagnation_worlds() const {
        return std::max<uint64_t>(256, uint64_t{8} * request_.beam_width * request_.children_per_branch);
    }

    void sample_batch() {
        const uint64_t count = std::min(request_.first_batch, request_.budget_worlds - made_);
        if (count == 0) return;
        const RunHeader& header = reader_.header();
        const CompiledScene compiled(scene_from_json(header.scene_json), header.parameters);
        std::vector<uint64_t> indices;
        for (uint64_t k = 0; k < count; ++k) indices.push_back(reader_.next_world_index() + k);
        sample_world_list(compiled, header.base_seed, indices, request_.threads,
                          [&](WorldResult&& world) {
                              writer_.append(world);
                              cache_.keep(world);
                          },
                          progress_);
        made_ += count;
        // Worlds sampled now are new candidates; spent ones stay spent.
    }

    SeekStatus status() const {
        SeekStatus s;
        s.box_count = static_cast<uint32_t>(request_.boxes.size());
        if (!ranking_.empty()) {
            s.best_world = best_world();
            s.best_value = scores_.at(s.best_world).value();
            s.best_boxes_met = scores_.at(s.best_world).boxes_met;
        }
        s.worlds_made = made_;
        s.worlds_meeting_goal = found_.size();
        s.seconds = elapsed();
        return s;
    }

    void report() const {
        if (on_status_) on_status_(status());
    }

    SeekOutcome outcome() const {
        SeekOutcome out;
        static_cast<SeekStatus&>(out) = status();
        out.reached = found_.size() >= request_.want;
        out.cancelled = progress_->cancel.load();
        out.found.assign(found_.begin(), found_.end());
        if (!ranking_.empty()) out.best_score = scores_.at(best_world());
        out.refinements = refinements_;
        return out;
    }

    SeekRequest request_;
    SeekListener on_status_;
    SamplingProgress own_progress_;
    SamplingProgress* progress_;
    LibraryReader reader_;
    LibraryWriter writer_;
    Scene scene_;
    PathIndex index_;
    LineageCache cache_;
    PortableRandom random_;
    std::chrono::steady_clock::time_point start_;
    std::vector<size_t> order_;

    std::unordered_map<uint64_t, size_t> position_;  ///< world index -> position in reader_.worlds()
    std::unordered_map<uint64_t, GoalScore> scores_;
    std::set<std::pair<double, uint64_t>> ranking_;  ///< (-value, world index): best first
    std::set<uint64_t> found_, spent_;
    std::set<long long> seen_values_;
    std::map<uint64_t, uint32_t> failures_;
    std::set<std::pair<uint64_t, Branch>> tried_;
    uint64_t made_ = 0, refinements_ = 0;
    double best_value_ = -1;
    uint64_t made_at_progress_ = 0;
};

}  // namespace

SeekOutcome seek_goal(const std::string& library_path, const SeekRequest& request, const SeekListener& on_status,
                      SamplingProgress* progress) {
    GoalSearch search(library_path, request, on_status, progress);
    return search.run();
}

}  // namespace mwb
