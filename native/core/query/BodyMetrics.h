#pragma once
// Per-body ranking metrics computed once from a world's full-rate motion, when it is stored.
#include <string>
#include <vector>

#include "sim/WorldResult.h"

namespace mwb {

/// Values of one metric, one per body of the world (scene order).
struct MetricValues {
    std::string name;
    std::vector<double> per_body;
};

/// Names of the stored metrics, in storage order:
/// - "angular_travel_rad": integrated angular speed, the sum of frame-to-frame rotation angles
///   (a sphere rolling without slipping: distance / radius);
/// - "time_to_rest_s": start of the body's final rest, or the world's end time;
/// - "collision_count": significant impacts on the body (the perturbation threshold);
/// - "orientation_change_rad": angle between the first and last recorded orientation;
/// - "path_length_m": length of the recorded origin path.
const std::vector<std::string>& stored_metric_names();

/// Computes every stored metric for every body of `world`.
std::vector<MetricValues> compute_body_metrics(const WorldResult& world);

}  // namespace mwb
