#include "seek/ScoredWorlds.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "geometry/ShapeBounds.h"
#include "seek/WorldIndexing.h"

namespace mwb {
namespace {

std::vector<double> body_radii(const Scene& scene) {
    std::vector<double> radii;
    for (const Body& b : scene.bodies) radii.push_back(body_bounding_radius(b));
    return radii;
}

}  // namespace

ScoredWorlds::ScoredWorlds(LibraryReader& reader, const Scene& scene, const std::vector<QueryBox>& boxes, int threads)
    : reader_(reader), boxes_(boxes), order_(goal_order(boxes)), index_(body_radii(scene)), threads_(threads) {}

void ScoredWorlds::take_new_worlds() {
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
    index_.add_worlds(std::move(inputs), threads_);
    // In index order, not file order (which depends on which thread finished first): which of
    // two equal worlds counts is then the same on any thread count.
    std::sort(fresh.begin(), fresh.end());
    for (uint64_t w : fresh) {
        GoalScore score = index_.score(w, boxes_, order_);
        if (score.first_unmet < 0) found_.insert(w);
        // A world that gets as far as one already scored (to a thousandth of a box) is, for
        // the goal, the same world: refining both would repeat work.
        else if (!seen_values_.insert(std::llround(score.value() * 1000)).second) spent_.insert(w);
        ranking_.insert(std::make_pair(-score.value(), w));
        scores_.emplace(w, std::move(score));
    }
}

uint64_t ScoredWorlds::family_of(uint64_t world) const {
    const StoredWorld& w = stored(world);
    return w.lineage.empty() ? w.world_index : w.root_world;
}

std::vector<uint64_t> ScoredWorlds::choose_beam(uint32_t width, uint32_t per_family) const {
    std::vector<uint64_t> beam;
    std::map<uint64_t, uint32_t> taken;
    for (const auto& [negative_value, world] : ranking_) {
        if (beam.size() >= width) break;
        if (found_.count(world) || spent_.count(world)) continue;
        if (taken[family_of(world)]++ >= per_family) continue;
        beam.push_back(world);
    }
    for (const auto& [negative_value, world] : ranking_) {
        if (beam.size() >= width) break;
        if (found_.count(world) || spent_.count(world)) continue;
        if (std::find(beam.begin(), beam.end(), world) == beam.end()) beam.push_back(world);
    }
    return beam;
}

}  // namespace mwb
