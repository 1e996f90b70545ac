#include "seek/BeamChoice.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mwb {

std::vector<uint64_t> choose_beam(const std::vector<BeamCandidate>& best_first, uint32_t width, uint32_t per_family,
                                  double reach_parts) {
    std::vector<uint64_t> beam;
    if (best_first.empty() || width == 0) return beam;
    // Whole parts: how near a family came to its next part does not make it a leader.
    const double leading_parts = std::floor(best_first.front().value);
    std::map<uint64_t, uint32_t> taken;
    for (const BeamCandidate& c : best_first) {
        if (beam.size() >= width) break;
        if (leading_parts - std::floor(c.value) > reach_parts) break;  // every later one is further behind
        if (taken[c.family]++ >= per_family) continue;
        beam.push_back(c.world);
    }
    for (const BeamCandidate& c : best_first) {
        if (beam.size() >= width) break;
        if (std::find(beam.begin(), beam.end(), c.world) == beam.end()) beam.push_back(c.world);
    }
    return beam;
}

}  // namespace mwb
