#pragma once
// The worlds a goal search has seen, scored against the goal, best first; and the beam of those
// it refines next.
#include <cstdint>
#include <array>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

#include "library/LibraryReader.h"
#include "seek/BeamChoice.h"
#include "query/GoalScore.h"
#include "query/PathIndex.h"
#include "scene/Scene.h"

namespace mwb {

class ScoredWorlds {
public:
    /// Scores the worlds `reader` reads (polylines on) against `boxes`; `threads` index them.
    ScoredWorlds(LibraryReader& reader, const Scene& scene, const std::vector<QueryBox>& boxes, int threads);

    /// Reads the worlds appended to the library since the last call and scores them, in world
    /// index order (the same on any thread count).
    void take_new_worlds();

    bool empty() const { return ranking_.empty(); }
    bool has(uint64_t world) const { return scores_.count(world) > 0; }
    const GoalScore& score(uint64_t world) const { return scores_.at(world); }
    const StoredWorld& stored(uint64_t world) const { return reader_.worlds()[position_.at(world)]; }
    /// The world meeting most of the goal (0 while there is none).
    uint64_t best_world() const { return ranking_.empty() ? 0 : ranking_.begin()->second; }
    double best_value() const { return ranking_.empty() ? 0.0 : -ranking_.begin()->first; }
    /// Every world meeting the whole goal.
    const std::set<uint64_t>& found() const { return found_; }
    /// The chance that a world sampled afresh meets the whole goal, judged by the sampled worlds
    /// (those with no parent) scored so far: per part, the share of them meeting it among those
    /// meeting the part it follows (all of them for a part that follows none), each smoothed
    /// toward a half while there are few, multiplied together; or the share meeting the whole
    /// goal when that is higher (parts that come together).
    double sampled_goal_odds() const;
    /// A world no refinement of which is worth trying any more.
    void spend(uint64_t world) { spent_.insert(world); }
    /// The sampled world `world` descends from (itself if sampled): its family.
    uint64_t family_of(uint64_t world) const;
    /// A family none of whose worlds goes into the beam any more (its refinements stopped paying).
    void set_aside(uint64_t family) { set_aside_.insert(family); }

    /// The beam (see BeamChoice.h) among the worlds not yet met or spent nor of a family set
    /// aside, best first (ties: lower index).
    std::vector<uint64_t> choose_beam(const BeamRule& rule) const;

private:
    // The scores of `worlds` (indexed already), in their order; on threads_ threads.
    std::vector<GoalScore> score_worlds(const std::vector<uint64_t>& worlds) const;

    LibraryReader& reader_;
    const std::vector<QueryBox>& boxes_;
    std::vector<size_t> order_;
    std::vector<uint32_t> oriented_bodies_;  ///< the bodies orientation parts name
    std::vector<uint32_t> goal_bodies_;      ///< the bodies any part names, sorted: the only ones indexed
    std::vector<size_t> ordered_parts_;      ///< the parts met after another, or another after them
    PathIndex index_;
    int threads_;
    std::unordered_map<uint64_t, size_t> position_;  ///< world index -> position in reader_.worlds()
    std::unordered_map<uint64_t, GoalScore> scores_;
    /// Per world, when it met the ordered parts before it broke a negative one, ascending (the
    /// beam's pace); none for a goal without order.
    std::unordered_map<uint64_t, std::vector<double>> ordered_met_s_;
    std::set<std::pair<double, uint64_t>> ranking_;  ///< (-value, world index): best first
    std::set<uint64_t> found_, spent_, set_aside_;
    std::set<std::array<long long, 3>> seen_values_;  ///< GoalScore::search_key of the worlds kept
    uint64_t sampled_ = 0, sampled_found_ = 0;  ///< sampled worlds scored, and of them those meeting the goal
    std::vector<uint64_t> sampled_meeting_;      ///< per part, the sampled worlds meeting it
};

}  // namespace mwb
