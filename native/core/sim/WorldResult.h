#pragma once
// Everything one sampled world produces: recorded motion, contact events, rest times and
// checkpoints. Positions and orientations are of the object's origin (what Blender keys);
// checkpoints hold the simulator's centre-of-mass state so a world can be restarted exactly.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/Math.h"
#include "sim/OdeMessages.h"

namespace mwb {

/// A collision of one body: the first step of a run of steps whose velocity change beyond gravity
/// exceeds the impact thresholds while touching something, or a step where it starts touching
/// another body during such a run. Each is perturbed once.
struct ContactEvent {
    double time_s = 0;
    int32_t body = -1;     ///< scene body index of the body whose velocity jumped
    int32_t other = -1;    ///< body it touched in that step (deepest contact), -1 if none found
    double impulse_ns = 0; ///< mass * |delta v| beyond gravity, N·s
};

/// Centre-of-mass state of one body, in the world frame.
struct BodyState {
    Vec3 position_m{0, 0, 0};
    Quat orientation{1, 0, 0, 0};
    Vec3 linear_velocity{0, 0, 0};
    Vec3 angular_velocity{0, 0, 0};
};

/// Full simulator state at the start of step `step_index` (time = step_index / step_hz).
struct Checkpoint {
    uint64_t step_index = 0;
    std::vector<BodyState> bodies;         ///< one per scene body
    std::vector<uint8_t> joint_broken;     ///< one per scene constraint
    uint64_t ode_random_state = 0;         ///< ODE's constraint-ordering generator
    std::array<uint64_t, 4> perturbation_random_state{};
    std::vector<double> body_rest_since_s; ///< per body, -1 when moving
    std::vector<double> body_quiet_since_s; ///< per body, below the sleep speeds since; -1 if not
    /// Per body: the partner of the impact under way in the previous step, kNoImpact if none.
    std::vector<int32_t> body_impact_partner;
};

/// body_impact_partner value of a body that was not in an impact in the previous step.
constexpr int32_t kNoImpact = -2;

enum class WorldStatus { Ok, Rejected, Cancelled };

/// One refinement in a world's lineage: from `branch_step` on, `bodies` (and whatever they
/// touch) are simulated anew with the perturbation stream of world `world_index`, while every
/// other body replays the world refined. A step may also change the scene, always from t = 0:
/// `added` bodies (scene indices beyond the refined world's) join it, simulated, with initial
/// states drawn from world `world_index`'s stream; `removed` bodies leave it, and a ghost of each
/// finds the bodies it used to touch.
struct RefineStep {
    uint64_t branch_step = 0;
    uint64_t world_index = 0;
    std::vector<uint32_t> bodies{};
    std::vector<uint32_t> added{};
    std::vector<uint32_t> removed{};
};

struct WorldResult {
    uint64_t world_index = 0;  ///< position in the run's seed range
    uint64_t seed = 0;         ///< derived from (base seed, world index)
    WorldStatus status = WorldStatus::Ok;
    std::string reject_reason;
    double record_hz = 120.0;
    double step_hz = 240.0;
    uint32_t first_frame = 0;              ///< > 0 when resumed from a checkpoint
    uint32_t frame_count = 0;              ///< recorded frames, frame i at time (first_frame + i) / record_hz
    uint32_t body_count = 0;
    std::vector<double> positions_m;       ///< (body_count, frame_count, 3) object origins
    std::vector<double> orientations;      ///< (body_count, frame_count, 4) w, x, y, z
    std::vector<ContactEvent> contacts;    ///< time-ordered
    std::vector<double> rest_time_s;       ///< per body: start of its final rest, or end time
    std::vector<Checkpoint> checkpoints;   ///< time-ordered, first at t = 0
    uint32_t impacts_perturbed = 0;
    double simulated_time_s = 0;
    /// Refined worlds: the original world and every refinement from it, this world's last.
    uint64_t root_world = 0;
    std::vector<RefineStep> lineage;
    /// Refined worlds: per body, 1 if it moved differently from the parent (was simulated anew).
    std::vector<uint8_t> changed;
    /// Per body, 1 if it exists in this world (0: removed in the lineage, or added only to other
    /// worlds). Frames of absent bodies hold their scene pose and are never stored.
    std::vector<uint8_t> present;
    /// What ODE said through its message handler while the world stepped (not stored).
    std::vector<OdeMessage> ode_messages;
};

}  // namespace mwb
