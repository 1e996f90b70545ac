#pragma once
// How long a family of worlds (a sampled world and its refinements) keeps its place in a goal
// search when its refinements stop meeting more parts.
#include <cstdint>
#include <map>
#include <vector>

namespace mwb {

/// A world as the allowance sees it.
struct FamilyWorld {
    double value = 0;     ///< GoalScore::value(): parts met, then closeness to the next
    /// It broke a negative part before meeting any positive one (GoalScore::violation_time_s is
    /// finite, positive_parts_before_violation 0): nothing of it is worth keeping.
    bool broken_start = false;
};

class FamilyAllowance {
public:
    enum class Verdict {
        Keep,         ///< the family keeps its place
        SetAside,     ///< its refinements made `stall_worlds` worlds without a gain
        BrokenStart,  ///< its best world is broken and they made `broken_worlds` without a gain
    };

    FamilyAllowance(uint64_t stall_worlds, uint64_t broken_worlds)
        : stall_worlds_(stall_worlds), broken_worlds_(broken_worlds) {}

    /// After a refinement of `refined`, a world of `family`, made `made` worlds, those scored in
    /// `children`. The allowance that applies is that of the family's best world so far, not of
    /// the world refined: on the staircase the leading family's best met 20 of 21 parts unbroken
    /// while its next worlds had gone over the string, and refining one of those gave the whole
    /// family up after 64 worlds.
    Verdict note(uint64_t family, const FamilyWorld& refined, const std::vector<FamilyWorld>& children, uint64_t made);

private:
    struct Record {
        FamilyWorld best;                ///< the best world of the family seen
        double parts = 0;                ///< the most parts a world of the family meets
        uint64_t worlds_since_gain = 0;  ///< worlds its refinements made since that rose
    };
    uint64_t stall_worlds_, broken_worlds_;
    std::map<uint64_t, Record> families_;
};

}  // namespace mwb
