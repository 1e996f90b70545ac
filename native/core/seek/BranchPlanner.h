#pragma once
// Where a goal search branches a world that misses its goal, and which of those points it tries
// next: how late in the part's span, learnt from which refinements paid; within that, later
// points first (they keep more of what the world got right), earlier ones as the world's
// children keep failing.
#include <array>
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

    /// An untried branch point of `world` (its record and score) for one of the parts it could
    /// meet next (those failed least often first, then the nearest). How late in the part's span
    /// to branch is learnt from the refinements so far; within that, the point is drawn near the
    /// one its failures point to (1, 2, 4, ... points earlier than the latest). Points that would
    /// put a met part at risk come only once no other point of any part is left, and a pose's that
    /// risk more than kFewRisked bodies holding met parts after those; false when every point of
    /// every such part has been tried.
    bool choose(uint64_t world, const StoredWorld& record, const GoalScore& score, Branch& chosen);

    /// How a refinement of `parent` went, on the part it was refined for: a child better than
    /// the parent by more than `gain` starts afresh, one that is not inherits its parent's
    /// failures plus one; the parent backs up unless some child was better.
    void note_children(uint64_t parent, double parent_value, const std::vector<std::pair<uint64_t, double>>& children,
                       double gain);

private:
    // How late in its part's span a point lies: the span cut in kLatenessBins equal lengths. Which
    // of them pays is learnt as the search goes (see choose_lateness).
    static constexpr size_t kLatenessBins = 4;
    // A pose's points that put more bodies holding met parts at risk than this come last. On
    // SIGGRAPH upright, of the children refined for a letter's pose that changed three or more
    // other letters, 0.2% stood it up losing nothing; of those that changed none, 3.2%.
    static constexpr size_t kFewRisked = 2;
    struct LatenessRecord {
        uint32_t refinements = 0;  ///< refinements branched at points this late
        uint32_t gains = 0;        ///< of them, those with a child meeting more parts than its parent
    };

    // Which points a pass of choose() offers: those that keep every met part; then those that put
    // some at risk (a pose's only up to kFewRisked bodies holding them); then a pose's that risk more.
    enum class RiskPass { KeepsEveryMetPart, RisksFew, RisksMany };
    // The points of one part it misses: where `miss` says it went wrong, by the bodies it blames;
    // those `pass` offers. `lateness`: each point's bin.
    std::vector<Branch> branch_points(const StoredWorld& w, const GoalScore& score, const GoalScore::Miss& miss,
                                      RiskPass pass, std::vector<size_t>& lateness) const;
    // A lateness bin among those with an open point: each drawn from what its refinements paid so
    // far (Thompson sampling), the best draw wins.
    size_t choose_lateness(const std::vector<size_t>& bins_open);
    // A draw from Beta(a, b), integer a and b >= 1, from this planner's own stream.
    double beta_draw(uint32_t a, uint32_t b);
    bool choose_for(uint64_t world, const StoredWorld& record, const GoalScore& score, const GoalScore::Miss& miss,
                    RiskPass pass, Branch& chosen);
    uint32_t failures_of(uint64_t world, int32_t part) const;
    // The failures that set how far back in the chosen length to branch: for a positive part all
    // of the part's, for a negative part only those refined in that length (see choose_for).
    uint32_t back_off_failures(uint64_t world, int32_t part, size_t bin) const;
    // The points worth refining at. Never one after which none of its bodies has an impact before
    // the world broke a negative part, if it did: with nothing perturbed that counts, its children
    // all score as the parent. Then those that put from `fewest_risked` to `most_risked` bodies
    // holding a met part at risk (re-simulate them, or pass a touch on to them): refining a letter
    // before its last touch of a letter already in its slot knocked that one out in most children
    // (SIGGRAPH, 3 minutes of a search: 78% of such children lost a letter, 0.1% gained one and
    // lost none, against 17% and 1.7% of the others).
    std::vector<Branch> worth_branching(const StoredWorld& w, const GoalScore& score,
                                        const std::set<uint32_t>& failing_set, const std::set<Branch>& points,
                                        size_t fewest_risked, size_t most_risked) const;
    bool simulated(uint32_t body) const;
    // `bodies` and every body joined to them through enabled constraints, transitively.
    std::set<uint32_t> jointed_with(const std::vector<uint32_t>& bodies) const;

    const Scene& scene_;
    const std::vector<QueryBox>& boxes_;
    PortableRandom random_;
    std::map<std::pair<uint64_t, int32_t>, uint32_t> failures_;  ///< (world, part): children that failed it
    /// (world, negative part): per length of its span, the refinements there whose children failed it
    std::map<std::pair<uint64_t, int32_t>, std::array<uint32_t, kLatenessBins>> length_failures_;
    std::map<uint64_t, int32_t> refined_part_;                     ///< world: the part last refined
    std::map<uint64_t, size_t> refined_lateness_;                  ///< world: the bin of its last branch point
    std::array<LatenessRecord, kLatenessBins> lateness_record_{};
    std::set<std::pair<uint64_t, Branch>> tried_;
};

}  // namespace mwb
