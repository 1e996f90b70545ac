#include "seek/BeamChoice.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace mwb {

int pace_lead(const BeamCandidate& world, const BeamCandidate& leader) {
    if (!world.ordered_met_s || world.ordered_met_s->empty()) return 0;
    const std::vector<double>& own = *world.ordered_met_s;
    static const std::vector<double> none;
    const std::vector<double>& lead = leader.ordered_met_s ? *leader.ordered_met_s : none;
    const auto leader_had = std::upper_bound(lead.begin(), lead.end(), own.back()) - lead.begin();
    return static_cast<int>(own.size()) - static_cast<int>(leader_had);
}

std::vector<uint64_t> choose_beam(const std::vector<BeamCandidate>& best_first, const BeamRule& rule) {
    std::vector<uint64_t> beam;
    if (best_first.empty() || rule.width == 0) return beam;
    // Whole parts: how near a family came to its next part does not make it a leader.
    const double leading_parts = std::floor(best_first.front().value);
    std::map<uint64_t, uint32_t> taken;
    for (const BeamCandidate& c : best_first) {
        if (beam.size() >= rule.width) break;
        if (leading_parts - std::floor(c.value) > rule.reach_parts) break;  // every later one is further behind
        if (taken[c.family]++ >= rule.per_family) continue;
        beam.push_back(c.world);
    }
    for (const BeamCandidate& c : best_first) {
        if (beam.size() >= rule.width) break;
        if (std::find(beam.begin(), beam.end(), c.world) == beam.end()) beam.push_back(c.world);
    }
    if (rule.pace_lead_parts == 0 || beam.size() < rule.width) return beam;  // not full: every world is in
    // The family furthest ahead of the leader's pace, by its best open world.
    std::set<uint64_t> families_in_beam, seen;
    for (const BeamCandidate& c : best_first)
        if (std::find(beam.begin(), beam.end(), c.world) != beam.end()) families_in_beam.insert(c.family);
    const BeamCandidate* fastest = nullptr;
    int fastest_lead = static_cast<int>(rule.pace_lead_parts) - 1;
    for (const BeamCandidate& c : best_first) {
        if (!seen.insert(c.family).second) continue;
        const int lead = pace_lead(c, best_first.front());
        if (lead > fastest_lead) fastest = &c, fastest_lead = lead;
    }
    if (fastest && !families_in_beam.count(fastest->family)) beam.back() = fastest->world;
    return beam;
}

}  // namespace mwb
