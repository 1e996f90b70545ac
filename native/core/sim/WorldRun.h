#pragma once
// Runs one world step by step: it owns the ODE world and wires the parts that drive animated
// bodies, generate contacts, respond to impacts, replay a refined world and record the run.
#include <atomic>
#include <cstdint>
#include <vector>

#include "sim/BodyInitialState.h"
#include "sim/BodyActivity.h"
#include "sim/BodySleep.h"
#include "sim/CompiledScene.h"
#include "sim/ContactGenerator.h"
#include "sim/ImpactResponse.h"
#include "sim/KinematicDriver.h"
#include "sim/OdeWorld.h"
#include "sim/RefinementReplay.h"
#include "sim/WorldRecorder.h"
#include "sim/WorldResult.h"

namespace mwb {

/// Runs once (run()); not thread-safe, but worlds on different threads run independently.
class WorldRun {
public:
    /// World `world_index` of a run with `base_seed`. `lineage`: the refinements this run will
    /// make (plan_refinements); the bodies they add or remove decide which bodies the world has.
    /// Throws OdeError if ODE cannot build the world.
    WorldRun(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
             const std::vector<RefineStep>& lineage = {});

    /// Starts from `checkpoint` of the same world instead of t = 0; it must outlive the run.
    void restore(const Checkpoint& checkpoint);
    /// Refinements to apply on the way: at steps[k].branch_step the run switches to simulating
    /// steps[k].bodies while the other bodies replay *parents[k], which must be full-length and
    /// outlive the run.
    void plan_refinements(const std::vector<RefineStep>& steps, const std::vector<const WorldResult*>& parents);
    /// Runs to the end, to rest, to rejection or until `cancel` (optional, polled every recorded
    /// frame) is set.
    WorldResult run(const std::atomic<bool>* cancel = nullptr);
    /// Body-steps not stepped because the body slept (sim/BodySleep), so far.
    uint64_t sleeping_body_steps() const { return sleep_.sleeping_body_steps(); }

private:
    /// The bodies a world has (per scene body, 1 if present) and their starting states.
    struct Bodies {
        std::vector<uint8_t> present;
        std::vector<BodyInitialState> initial;
    };
    static Bodies draw_bodies(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                              const std::vector<RefineStep>& lineage);
    WorldRun(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index, const Bodies& bodies);

    void loop(const std::atomic<bool>* cancel);
    void step_once();
    bool at_rest(double t_s) const;
    void reject(const char* reason);
    void finish();

    const CompiledScene& compiled_;
    uint64_t base_seed_;
    OdeWorld world_;
    BodyActivity activity_;
    ContactGenerator contacts_;
    ImpactResponse impacts_;
    BodySleep sleep_;
    KinematicDriver kinematics_;
    RefinementReplay replay_;
    WorldRecorder recorder_;
    WorldResult result_;
    uint64_t step_ = 0;
    /// ODE's constraint-ordering generator. The same start for every world: worlds differ only by
    /// their initial states and perturbations, not by solver noise.
    uint64_t ode_random_state_ = 0;
};

}  // namespace mwb
