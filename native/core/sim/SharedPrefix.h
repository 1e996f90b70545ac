#pragma once
// Worlds of a run whose initial states do not vary are one and the same world until the first
// perturbed impact: only the perturbation stream, drawn from at impacts, tells them apart. The
// prefix is simulated once; every later world starts from the source world's last checkpoint
// before that impact and takes the earlier frames and checkpoints from it.
#include <atomic>
#include <cstdint>
#include <optional>

#include "sim/CompiledScene.h"
#include "sim/WorldResult.h"

namespace mwb {

/// True when no body sampled in the run varies its initial state (every variation range is a
/// single value), so that every world of the run starts alike.
bool worlds_start_alike(const CompiledScene& compiled);

/// Simulates worlds of one run, sharing their common prefix when `share` and worlds_start_alike:
/// the first world that completes is simulated in full and becomes the source of the prefix.
/// Every result is bit for bit what simulate_world gives. Not thread-safe: one per thread.
class PrefixSharingSimulator {
public:
    PrefixSharingSimulator(const CompiledScene& compiled, uint64_t base_seed, bool share);

    WorldResult simulate(uint64_t world_index, const std::atomic<bool>* cancel = nullptr);

    /// The step later worlds start from; 0 while there is no shared prefix (none yet, sharing
    /// off, worlds that vary, or a first perturbed impact before the first checkpoint after t = 0).
    uint64_t shared_steps() const { return branch_ ? branch_->step_index : 0; }

private:
    void keep_prefix_of(const WorldResult& source);
    void splice_prefix(WorldResult& resumed) const;

    const CompiledScene& compiled_;
    uint64_t base_seed_;
    bool share_;  ///< still looking for a prefix to share (off once a complete world had none)
    /// The source's checkpoint later worlds start from, and what came before it.
    std::optional<Checkpoint> branch_;
    uint32_t prefix_frames_ = 0;
    std::vector<double> prefix_positions_m_;  ///< (body, frame, 3)
    std::vector<double> prefix_orientations_; ///< (body, frame, 4)
    std::vector<Checkpoint> prefix_checkpoints_;
};

}  // namespace mwb
