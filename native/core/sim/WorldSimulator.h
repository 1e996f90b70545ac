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

/// FNV-1a hash over everything a world recorded (motion, events, rest times, checkpoints).
uint64_t hash_world(const WorldResult& world);

}  // namespace mwb
