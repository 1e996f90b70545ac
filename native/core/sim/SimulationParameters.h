#pragma once
// Parameters of a sampling run that are not part of the scene. Defaults follow SPEC §4.
#include <cmath>
#include <cstdint>

#include "scene/Scene.h"

namespace mwb {

struct SimulationParameters {
    /// Simulated duration in seconds of animation time; <= 0 means the scene's frame range.
    double duration_s = 0;
    /// End a world early once every dynamic body has rested for `rest_duration_s`.
    bool stop_at_rest = true;
    /// Minimum stepping rate; the actual rate is a multiple of `record_hz` and at least the
    /// scene's fps × substeps.
    double min_step_hz = 240;
    double record_hz = 120;
    /// Perturbation strength: magnitudes are uniform in ±alpha·|Δv| (linear) and ±alpha·|Δω|.
    double alpha_linear = 0.1;
    double alpha_angular = 0.1;
    /// Exponent n of the cos^n lobe the perturbation direction is drawn from.
    double lobe_exponent = 50;
    /// Impact thresholds as multiples of dt·|g| (linear, m/s) and dt·π (angular, rad/s).
    double impact_linear_factor = 2;
    double impact_angular_factor = 2;
    /// A body rests while |v| and |ω| stay below these.
    double rest_linear_speed = 0.05;   ///< m/s
    double rest_angular_speed = 0.1;   ///< rad/s
    double rest_duration_s = 0.5;
    double checkpoint_interval_s = 0.5;
    /// A world whose body exceeds these has exploded and is rejected.
    double max_speed_mps = 500;
    double max_distance_m = 10000;
    /// Record and perturb; off gives the unperturbed reference simulation.
    bool perturb = true;
    /// Sleeping (sim/BodySleep): a body below these speeds for the delay stops being stepped until
    /// an awake body reaches it. Thresholds as in the original sampler (0.001), so a sleeping body
    /// would have moved less than the codec's error bound.
    bool sleep = true;
    double sleep_linear_speed = 0.001;   ///< m/s
    double sleep_angular_speed = 0.01;   ///< rad/s
    double sleep_delay_s = 0.5;
};

/// Seconds every world of a run covers: `duration_s` when set, else the scene's frame range.
inline double run_duration_s(const SimulationParameters& parameters, const WorldSettings& world) {
    return parameters.duration_s > 0 ? parameters.duration_s : (world.frame_end - world.frame_start) / world.fps;
}

/// The run's last recorded frame. A world that ends earlier (every body at rest) holds its final
/// pose from its own last frame up to this one; no world has a pose beyond it.
inline uint64_t run_last_frame(const SimulationParameters& parameters, const WorldSettings& world) {
    return static_cast<uint64_t>(std::llround(run_duration_s(parameters, world) * parameters.record_hz));
}

}  // namespace mwb
