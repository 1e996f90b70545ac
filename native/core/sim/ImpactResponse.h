#pragma once
// What a world does after each ODE step, body by body: it detects collisions and perturbs them
// (plausible motion, Twigg & James 2007), applies Blender's damping, rejects implausible states
// and tracks when bodies come to rest.
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "sim/BodyActivity.h"
#include "sim/CompiledScene.h"
#include "sim/ContactGenerator.h"
#include "sim/ImpactPerturber.h"
#include "sim/OdeWorld.h"
#include "sim/PortableRandom.h"
#include "sim/WorldResult.h"

namespace mwb {

/// Thrown when a body becomes non-finite, too fast or too far away; the world is rejected with
/// this reason.
struct WorldRejected : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// One per world run; not thread-safe (a world runs on one thread).
class ImpactResponse {
public:
    /// `perturbation_seed`: seed of the world's perturbation stream.
    ImpactResponse(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity, uint64_t perturbation_seed);

    /// Remembers the simulated bodies' velocities; call right before ODE steps.
    void capture_velocities_before_step();
    /// After ODE stepped from step `step` to time `t_after_s`: every simulated body that no longer
    /// follows its animation gets its collisions perturbed and recorded, its velocities damped,
    /// and its rest tracked. Throws WorldRejected for an implausible body.
    void respond_to_step(const ContactGenerator& contacts, uint64_t step, double t_after_s);
    /// Whether every simulated body has rested for the run's rest duration at `t_s`.
    bool simulated_bodies_at_rest(double t_s) const;

    /// Since when body i has stayed below its sleep speeds (sim/BodySleep); kNotQuiet while it
    /// moves. A body set to start deactivated has been quiet since long before the start.
    double quiet_since_s(size_t i) const { return quiet_since_s_[i]; }
    static constexpr double kNotQuiet = -1.0;
    /// A body woken at `t_s` counts as quiet from then on, as Bullet restarts a woken body's
    /// deactivation time: it must stay quiet for the whole delay again before it sleeps.
    void restart_quiet(size_t i, double t_s) { quiet_since_s_[i] = t_s; }
    static constexpr double kQuietSinceBeforeStart = -1.0e9;
    /// Refinement: body i is simulated anew, with no collision under way and not at rest.
    void restart_body(size_t i);
    /// Refinement: perturbations draw from the stream with `seed` from now on.
    void reseed_perturbations(uint64_t seed) { perturbation_random_ = PortableRandom(seed); }

    /// Stores the perturbation stream, rest and collision state in `checkpoint`.
    void save(Checkpoint& checkpoint) const;
    void restore(const Checkpoint& checkpoint);
    /// Moves the recorded collisions into `result` and sets its bodies' rest times for a world
    /// that ended at `end_s`.
    void finish(double end_s, WorldResult& result);

private:
    void respond(size_t i, const DeepestContact& contact, double t_after_s);
    Vec3 point_velocity_before_step(int32_t i, const Vec3& point) const;
    double approach_speed(size_t i, const DeepestContact& contact) const;

    const CompiledScene& compiled_;
    OdeWorld& world_;
    const BodyActivity& activity_;
    PortableRandom perturbation_random_;
    ImpactPerturber perturber_;
    ImpactPerturber angular_perturber_;
    double linear_threshold_ = 0;   ///< m/s: velocity jump and approach speed of an impact
    double angular_threshold_ = 0;  ///< rad/s
    std::vector<double> linear_damping_factor_, angular_damping_factor_;  ///< per body, per step
    std::vector<Vec3> previous_linear_, previous_angular_;                ///< per body, before the step
    std::vector<double> rest_since_s_;    ///< per body, -1 while moving
    std::vector<double> quiet_since_s_;   ///< per body, kNotQuiet while above its sleep speeds
    std::vector<double> sleep_linear_speed_, sleep_angular_speed_;  ///< per body
    std::vector<int32_t> impact_partner_;  ///< per body, kNoImpact after a quiet step
    std::vector<ContactEvent> collisions_;
    uint32_t impacts_perturbed_ = 0;
};

}  // namespace mwb
