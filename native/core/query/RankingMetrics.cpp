#include "query/RankingMetrics.h"

namespace mwb {

const std::vector<RankingMetric>& ranking_metrics() {
    static const std::vector<RankingMetric> metrics{
        {"angular_travel_rad", "Angular Travel", "rad", "Integrated angular speed (how much the bodies spin)"},
        {"time_to_rest_s", "Time to Rest", "s", "When the bodies came to rest"},
        {"collision_count", "Collisions", "hits", "How many collisions the bodies had"},
        {"orientation_change_rad", "Orientation Change", "rad", "Angle between the first and last orientation"},
        {"path_length_m", "Path Length", "m", "How far the bodies' origins travelled"},
        {"orientation_to_goal_rad", "Upright", "rad", "Angle of the final orientation from the object's unrotated pose"},
        {"boxes_met", "Goal Parts Met", "parts",
         "How many enabled goal parts (boxes and poses) each world meets; lists every world, not only the matching "
         "ones"},
    };
    return metrics;
}

}  // namespace mwb
