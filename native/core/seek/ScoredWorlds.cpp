#include "seek/ScoredWorlds.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include <omp.h>

#include "geometry/ShapeBounds.h"
#include "library/WorldDecoding.h"
#include "seek/WorldIndexing.h"

namespace mwb {
namespace {

std::vector<double> body_radii(const Scene& scene) {
    std::vector<double> radii;
    for (const Body& b : scene.bodies) radii.push_back(body_bounding_radius(b));
    return radii;
}

std::vector<size_t> ordered_parts(const std::vector<QueryBox>& boxes) {
    std::vector<uint8_t> ordered(boxes.size(), 0);
    for (size_t k = 0; k < boxes.size(); ++k)
        if (boxes[k].after >= 0) ordered[k] = ordered[static_cast<size_t>(boxes[k].after)] = 1;
    std::vector<size_t> parts;
    for (size_t k = 0; k < boxes.size(); ++k)
        if (ordered[k]) parts.push_back(k);
    return parts;
}

}  // namespace

ScoredWorlds::ScoredWorlds(LibraryReader& reader, const Scene& scene, const std::vector<QueryBox>& boxes, int threads)
    : reader_(reader),
      boxes_(boxes),
      order_(goal_order(boxes)),
      oriented_bodies_(posed_bodies(boxes)),
      goal_bodies_(named_bodies(boxes)),
      ordered_parts_(ordered_parts(boxes)),
      index_(body_radii(scene)),
      threads_(threads),
      sampled_meeting_(boxes.size(), 0) {}

void ScoredWorlds::take_new_worlds() {
    reader_.poll();
    std::vector<IndexedWorldInput> inputs;
    std::vector<uint64_t> fresh;
    for (size_t k = 0; k < reader_.worlds().size(); ++k) {
        const StoredWorld& w = reader_.worlds()[k];
        if (position_.count(w.world_index)) continue;
        position_[w.world_index] = k;
        // Only the bodies the goal names: on the staircase (99 of its 110 bodies are treads and
        // strings) indexing every path was most of the time the search spent between refinements,
        // while the workers waited.
        inputs.push_back(indexed_world_input(reader_, w, &goal_bodies_));
        fresh.push_back(w.world_index);
    }
    index_.add_worlds(std::move(inputs), threads_);
    // In index order, not file order (which depends on which thread finished first): which of
    // two equal worlds counts is then the same on any thread count.
    std::sort(fresh.begin(), fresh.end());
    std::vector<GoalScore> scores = score_worlds(fresh);
    for (size_t n = 0; n < fresh.size(); ++n) {
        const uint64_t w = fresh[n];
        GoalScore& score = scores[n];
        if (score.first_unmet < 0) found_.insert(w);
        // A world that gets as far as one already scored (to a thousandth of a box), and first
        // enters a negative part at the same moment, is for the goal the same world: refining
        // both would repeat work.
        else if (!seen_values_.insert(score.search_key()).second) spent_.insert(w);
        if (stored(w).lineage.empty()) {
            ++sampled_;
            if (score.first_unmet < 0) ++sampled_found_;
            for (size_t k = 0; k < score.met.size() && k < sampled_meeting_.size(); ++k) sampled_meeting_[k] += score.met[k];
        }
        ranking_.insert(std::make_pair(-score.value(), w));
        if (!ordered_parts_.empty()) {
            std::vector<double>& times = ordered_met_s_[w];
            for (size_t k : ordered_parts_)
                if (score.met[k] && score.met_time_s[k] <= score.violation_time_s) times.push_back(score.met_time_s[k]);
            std::sort(times.begin(), times.end());
        }
        scores_.emplace(w, std::move(score));
    }
}

std::vector<GoalScore> ScoredWorlds::score_worlds(const std::vector<uint64_t>& worlds) const {
    // Each world's score needs only its own paths and rotations: on all the threads given (the
    // staircase's 21 parts take about 11 ms a world, one refinement's 8 children 90 ms on one).
    std::vector<GoalScore> scores(worlds.size());
    std::vector<std::exception_ptr> errors(worlds.size());
    const auto count = static_cast<std::ptrdiff_t>(worlds.size());
    const int thread_count = threads_ > 0 ? threads_ : omp_get_max_threads();
#pragma omp parallel for num_threads(thread_count) schedule(dynamic, 1)
    for (std::ptrdiff_t k = 0; k < count; ++k) {
        const auto n = static_cast<size_t>(k);
        try {
            BodyOrientations orientations;
            if (!oriented_bodies_.empty()) orientations = rotations_at_path_points(stored(worlds[n]), oriented_bodies_);
            scores[n] = index_.score(worlds[n], boxes_, order_, &orientations);
        } catch (...) {
            errors[n] = std::current_exception();
        }
    }
    for (const std::exception_ptr& error : errors)
        if (error) std::rethrow_exception(error);
    return scores;
}

double ScoredWorlds::sampled_goal_odds() const {
    double odds = 1.0;
    for (size_t k = 0; k < boxes_.size(); ++k) {
        const int32_t after = boxes_[k].after;
        const uint64_t reaching = after >= 0 ? sampled_meeting_[static_cast<size_t>(after)] : sampled_;
        odds *= (static_cast<double>(sampled_meeting_[k]) + 0.5) / (static_cast<double>(reaching) + 1.0);
    }
    const double whole = sampled_ > 0 ? static_cast<double>(sampled_found_) / static_cast<double>(sampled_) : 0.0;
    return std::max(odds, whole);
}

uint64_t ScoredWorlds::family_of(uint64_t world) const {
    const StoredWorld& w = stored(world);
    return w.lineage.empty() ? w.world_index : w.root_world;
}

std::vector<uint64_t> ScoredWorlds::choose_beam(const BeamRule& rule) const {
    std::vector<BeamCandidate> open;
    for (const auto& [negative_value, world] : ranking_)
        if (!found_.count(world) && !spent_.count(world) && !set_aside_.count(family_of(world))) {
            const auto ordered = ordered_met_s_.find(world);
            open.push_back({world, family_of(world), -negative_value,
                            ordered == ordered_met_s_.end() ? nullptr : &ordered->second});
        }
    return mwb::choose_beam(open, rule);
}

}  // namespace mwb
