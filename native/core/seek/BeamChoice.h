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
    /// When it met the goal's ordered parts (those met after another, and those another is met
    /// after), ascending, before it broke any negative part; null or empty for a goal without
    /// order. Where it stands on the way the goal orders.
    const std::vector<double>* ordered_met_s = nullptr;
};

/// How the beam is chosen.
struct BeamRule {
    uint32_t width = 4;
    uint32_t per_family = 1;
    /// A family more whole parts behind the best world than this gives its place up.
    double reach_parts = 3;
    /// A family this many ordered parts ahead of the best world's pace takes the beam's last place
    /// (0: never).
    uint32_t pace_lead_parts = 2;
};

/// How many ordered parts `world` was ahead of `leader` when it met its last: the ordered parts it
/// had met then, less those the leader had met by the same moment.
int pace_lead(const BeamCandidate& world, const BeamCandidate& leader);

/// At most `rule.width` worlds of `best_first` (sorted best first). First, at most
/// `rule.per_family` worlds of each family whose best world is at most `rule.reach_parts` parts
/// behind the best world of all; then, while the beam is not full, the best of the rest, whatever
/// their family. So a family far behind gives its place to the leading families' next best worlds,
/// and takes one again only when nothing nearer is left. But when a goal orders its parts, the
/// family furthest ahead of the best world's pace (by at least `rule.pace_lead_parts`; on a tie the
/// better) has the last place if it has none: a start that met three steps in five seconds is
/// refined beside a leader that took twelve, which would meet more parts only if it had time left.
std::vector<uint64_t> choose_beam(const std::vector<BeamCandidate>& best_first, const BeamRule& rule);

}  // namespace mwb
