#pragma once
// The metrics worlds can be ranked by, stated once for every front end: name, label, unit, help.
#include <string>
#include <vector>

namespace mwb {

struct RankingMetric {
    std::string name;   ///< identifier, as stored and as the command line takes it
    std::string label;  ///< for people, a few words
    std::string unit;   ///< "rad", "s", "m", "hits" or "boxes"
    std::string help;   ///< one sentence
};

/// The stored per-body metrics (stored_metric_names(), in that order), then those computed at
/// query time: "orientation_to_goal_rad" and "boxes_met" (enabled boxes each world meets; every
/// world is listed, not only the matching ones).
const std::vector<RankingMetric>& ranking_metrics();

}  // namespace mwb
