#pragma once
// Samples many worlds in parallel (OpenMP) and hands each to the caller as soon as it finishes.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "sim/CompiledScene.h"
#include "sim/WorldResult.h"

namespace mwb {

/// The worlds of a run in which ODE gave one kind of message.
struct OdeMessageReport {
    std::string text;          ///< the first world's first message of this kind
    uint64_t first_world = 0;  ///< the lowest world index that gave it
    double first_time_s = 0;   ///< when in that world
    uint64_t worlds = 0;       ///< how many worlds gave it
};
/// ODE's message number -> the worlds that gave messages of that number.
using OdeMessageReports = std::map<int, OdeMessageReport>;

struct SamplingStatistics {
    uint64_t worlds_ok = 0;
    uint64_t worlds_rejected = 0;
    uint64_t worlds_cancelled = 0;
    std::map<std::string, uint64_t> reject_reasons;  ///< reason -> count
    OdeMessageReports ode_messages;
    double wall_time_s = 0;
};

/// Adds the messages world `world_index` gave (WorldResult::ode_messages) to `reports`.
void note_ode_messages(OdeMessageReports& reports, uint64_t world_index, const std::vector<OdeMessage>& messages);
/// Adds `from` to `into` (the runs of one command).
void merge_ode_messages(OdeMessageReports& into, const OdeMessageReports& from);
/// One warning a person reads: the message, how many worlds, the first and when.
std::string describe_ode_messages(const OdeMessageReport& report);

/// Progress a caller on another thread may read while a run goes on.
struct SamplingProgress {
    std::atomic<uint64_t> worlds_done{0};
    std::atomic<bool> cancel{false};
};

/// Called once per finished world (Ok, Rejected or Cancelled), from a worker thread, never
/// concurrently with itself; worlds come in the order they were asked for, whichever finished
/// first, so that a library written from them is the same file on any thread count.
using WorldSink = std::function<void(WorldResult&&)>;

/// Simulates worlds [first_world, first_world + world_count) of the run seeded by `base_seed` on
/// `threads` threads (<= 0: all cores). Each world is a pure function of (scene, parameters,
/// base_seed, index), whatever the thread count or order. Setting progress->cancel stops every
/// world at its next recorded frame; worlds finished before then are delivered intact.
/// `share_prefix`: when no initial state varies, worlds start from the checkpoint before the
/// first perturbed impact of an earlier world (sim/SharedPrefix); the worlds are the same.
SamplingStatistics sample_worlds(const CompiledScene& compiled, uint64_t base_seed, uint64_t first_world,
                                 uint64_t world_count, int threads, const WorldSink& sink,
                                 SamplingProgress* progress = nullptr, bool share_prefix = true);

/// The same for an explicit list of world indices (e.g. the ones a library does not hold yet).
SamplingStatistics sample_world_list(const CompiledScene& compiled, uint64_t base_seed,
                                     const std::vector<uint64_t>& world_indices, int threads, const WorldSink& sink,
                                     SamplingProgress* progress = nullptr, bool share_prefix = true);

/// Refines the world at the end of `chain` (an exact lineage, see simulate_lineage) once per
/// entry of `children`, in parallel; each child's perturbations come from its own world index.
SamplingStatistics refine_worlds(const CompiledScene& compiled, uint64_t base_seed, const std::vector<WorldResult>& chain,
                                 const std::vector<RefineStep>& children, int threads, const WorldSink& sink,
                                 SamplingProgress* progress = nullptr);

}  // namespace mwb
