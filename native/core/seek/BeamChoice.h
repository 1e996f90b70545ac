#pragma once
// Which worlds a goal search refines next: its beam, chosen from the open worlds best first.
#include <cstdint>
#include <vector>

namespace mwb {

/// A world the search may refine, as the beam sees it.
struct BeamCandidate {
    uint64_t world = 0;
    uint64_t family = 0;  ///< the sampled world it descends from (itself if sampled)
    double value = 0;     ///< GoalScore::value(): parts met, then closeness to the next
};

/// At most `width` worlds of `best_first` (sorted best first). First, at most `per_family` worlds
/// of each family whose best world is at most `reach_parts` parts behind the best world of all;
/// then, while the beam is not full, the best of the rest, whatever their family. So a family far
/// behind gives its place to the leading families' next best worlds, and takes one again only
/// when nothing nearer is left.
std::vector<uint64_t> choose_beam(const std::vector<BeamCandidate>& best_first, uint32_t width, uint32_t per_family,
                                  double reach_parts);

}  // namespace mwb
