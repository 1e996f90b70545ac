#pragma once
// Simulates one plausible world: a pure function of (compiled scene, parameters, world seed).
#include <atomic>
#include <cstdint>

#include "sim/CompiledScene.h"
#include "sim/WorldResult.h"

namespace mwb {

/// Simulates world `world_index` of a run with `base_seed` from t = 0. Never throws for simulation
/// failures: an exploded world or an ODE internal error comes back Rejected with a reason.
/// `cancel` (optional) is polled every recorded frame; a cancelled world comes back Cancelled.
WorldResult simulate_world(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                           const std::atomic<bool>* cancel = nullptr);

/// Re-simulates the same world from one of its checkpoints; the frames from the checkpoint on are
/// bit-identical to the original run's. The result's first_frame is the checkpoint's frame.
WorldResult resume_world(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                         const Checkpoint& checkpoint, const std::atomic<bool>* cancel = nullptr);

/// The exact worlds of a lineage: [0] is world `root_world`, [k] the world after lineage[0..k).
/// Each refinement restarts from the original world's checkpoint at or before the first branch
/// and replays every earlier refinement, so a refined world equals its parent bit for bit before
/// its branch and every body it did not touch equals the parent for the whole world.
std::vector<WorldResult> simulate_lineage(const CompiledScene& compiled, uint64_t base_seed, uint64_t root_world,
                                          const std::vector<RefineStep>& lineage,
                                          const std::atomic<bool>* cancel = nullptr);

/// What check_refinement needs to know of the world refined (a stored world tells it without
/// being simulated again).
struct RefinedParent {
    uint64_t world_index = 0;
    uint32_t frame_count = 0;
    std::vector<uint8_t> present{};  ///< per scene body; empty: every body
};

/// Throws std::invalid_argument (saying why) if `step` cannot refine `parent`.
void check_refinement(const CompiledScene& compiled, const RefinedParent& parent, const RefineStep& step);
/// The same for the end of `chain`, which must also be a complete, valid, exact lineage.
void check_refinement(const CompiledScene& compiled, const std::vector<WorldResult>& chain, const RefineStep& step);

/// One refinement of an exact lineage `chain` (as simulate_lineage returns): world `step`.
WorldResult refine_world(const CompiledScene& compiled, uint64_t base_seed, const std::vector<WorldResult>& chain,
                         const RefineStep& step, const std::atomic<bool>* cancel = nullptr);

/// FNV-1a hash over everything a world recorded (motion, events, rest times, checkpoints).
uint64_t hash_world(const WorldResult& world);

}  // namespace mwb
