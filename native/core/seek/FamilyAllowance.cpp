#include "seek/FamilyAllowance.h"

#include <algorithm>
#include <cmath>

namespace mwb {

FamilyAllowance::Verdict FamilyAllowance::note(uint64_t family, const FamilyWorld& refined,
                                               const std::vector<FamilyWorld>& children, uint64_t made) {
    auto [it, first_time] = families_.try_emplace(family);
    Record& record = it->second;
    if (first_time) {
        record.best = refined;
        record.parts = std::floor(refined.value);
    }
    // The world refined may be better than any seen (a resumed search's library holds it).
    if (refined.value > record.best.value) record.best = refined;
    double best_child = -1;
    for (const FamilyWorld& child : children) {
        if (child.value > record.best.value) record.best = child;
        best_child = std::max(best_child, std::floor(child.value));
    }
    if (best_child > record.parts) {
        record.parts = best_child;
        record.worlds_since_gain = 0;
        return Verdict::Keep;
    }
    record.worlds_since_gain += made;
    const bool broken = record.best.broken_start;
    if (record.worlds_since_gain < (broken ? broken_worlds_ : stall_worlds_)) return Verdict::Keep;
    return broken ? Verdict::BrokenStart : Verdict::SetAside;
}

}  // namespace mwb
