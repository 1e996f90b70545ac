#pragma once
// Where a goal search branches a world that misses its goal, and which of those points it tries
// next: later points first (they keep more of what the world got right), earlier ones as the
// world's children keep failing.
#include <cstdint>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "library/WorldRecord.h"
#include "query/GoalScore.h"
#include "query/PathIndex.h"
#include "scene/Scene.h"
#include "sim/PortableRandom.h"

namespace mwb {

/// A refinement of one world: the recorded frame it leaves the parent at, the bodies simulated anew.
struct Branch {
    uint64_t frame = 0;
    std::vector<uint32_t> bodies;
    bool operator<(const Branch& o) const { return std::tie(frame, bodies) < std::tie(o.frame, o.bodies); }
    bool operator==(const Branch& o) const { return frame == o.frame && bodies == o.bodies; }
};

class BranchPlanner {
public:
    /// `seed`: the search's own; the same seed tries the same points in the same order.
    BranchPlanner(const Scene& scene, const std::vector<QueryBox>& boxes, uint64_t seed);

    /// An untried branch point of `world` (its record and score), drawn near the point its
    /// failures so far point to (1, 2, 4, ... points earlier than the latest); false when every
    /// point has been tried.
    bool choose(uint64_t world, const StoredWorld& record, const GoalScore& score, Branch& chosen);

    /// How a refinement of `parent` went: a child better than the parent by more than `gain`
    /// starts afresh, one that is not inherits its parent's failures plus one; the parent backs
    /// up unless some child was better.
    void note_children(uint64_t parent, double parent_value, const std::vector<std::pair<uint64_t, double>>& children,
                       double gain);

private:
    std::vector<Branch> branch_points(const StoredWorld& w, const GoalScore& score) const;
    bool simulated(uint32_t body) const;
    // `bodies` and every body joined to them through enabled constraints, transitively.
    std::set<uint32_t> jointed_with(const std::vector<uint32_t>& bodies) const;

    const Scene& scene_;
    const std::vector<QueryBox>& boxes_;
    PortableRandom random_;
    std::map<uint64_t, uint32_t> failures_;
    std::set<std::pair<uint64_t, Branch>> tried_;
};

}  // namespace mwb
