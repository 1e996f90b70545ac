#pragma once
// Sleeping: a simulated body that has stayed nearly still (below the sleep speeds) for the sleep
// delay stops being stepped and collided, until an awake body touches it. Which bodies
// sleep after a step follows from how long each has been quiet (ImpactResponse keeps that in
// checkpoints), so a world restarted from any checkpoint sleeps and wakes exactly as it did.
// Contacts are only made between bodies that are awake (or an awake body and a fixed one), so
// ODE never sees a joint to a disabled body. Jointed bodies never sleep: their joints pass
// forces every step. Keyed bodies sleep only after their handoff to the simulation.
#include <cstdint>
#include <vector>

#include "sim/BodyActivity.h"
#include "sim/CompiledScene.h"
#include "sim/ContactGenerator.h"
#include "sim/ImpactResponse.h"
#include "sim/OdeWorld.h"

namespace mwb {

class BodySleep {
public:
    BodySleep(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity, ImpactResponse& impacts);

    bool asleep(size_t i) const { return asleep_[i] != 0; }
    /// Before contacts are made in step `step`: wakes every sleeping body an awake body touches,
    /// and what those touch in turn.
    void wake_touched(const ContactGenerator& contacts, uint64_t step);
    /// After step `step`, at time `t_after_s`: bodies quiet for the sleep delay fall asleep.
    void settle(uint64_t step, double t_after_s);
    /// The bodies asleep at `step` (time `t_s`): at the start, or restarted from a checkpoint.
    void restore(uint64_t step, double t_s);
    /// Body-steps skipped so far (for benchmarks).
    uint64_t sleeping_body_steps() const { return sleeping_body_steps_; }

private:
    bool can_sleep(size_t i, uint64_t step) const;
    bool quiet_long_enough(size_t i, double t_s) const;
    void fall_asleep(size_t i);
    /// Wakes body i at `t_s`: its quiet time starts again.
    void wake(size_t i, double t_s);
    void enable(size_t i);
    /// Has an ODE body that is stepped or driven this step (not fixed, not asleep).
    bool moves(int32_t i) const;

    const CompiledScene& compiled_;
    OdeWorld& world_;
    const BodyActivity& activity_;
    ImpactResponse& impacts_;
    bool enabled_;
    std::vector<uint8_t> asleep_, jointed_;
    std::vector<double> delay_s_;  ///< per body: how long it must be quiet to fall asleep
    uint64_t sleeping_body_steps_ = 0;
};

}  // namespace mwb
