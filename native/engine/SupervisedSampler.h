#pragma once
// Worlds simulated in worker processes under a supervisor, so that no world can end a run: a
// world that makes ODE abort, crash or hang takes down only its worker. The supervisor stores it
// as a rejection naming the fault, starts a new worker and goes on; every other world is stored
// exactly as an in-process run would store it (a world is a pure function of its index and
// lineage). Sampling, refinement and the goal search all run their worlds this way.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "library/LibraryWriter.h"
#include "refine/WorldMaker.h"
#include "sampler/Sampler.h"

namespace mwb {

struct SupervisedRun {
    std::string engine_path;               ///< the engine executable the workers run
    std::vector<std::string> worker_args;  ///< their arguments, "worker" first
    int workers = 1;                       ///< processes at once, one world each
    uint64_t base_seed = 0;                ///< for the seeds of rejections the supervisor writes
    /// A world still running after this many seconds is stopped and rejected. <= 0: 600 s until a
    /// world has finished, then 20 times the slowest finished world (at least 60 s).
    double world_time_limit_s = 0;
};

/// Called in the supervisor's thread as each world arrives (or is rejected for a fault), before
/// its record may be appended: records are appended in task order; `reason` says why a rejected
/// world was rejected.
using SupervisedWorldSink = MadeWorldSink;

/// One world for a worker: its index and the line that tells the worker what to simulate
/// (engine/WorkerJob.h).
struct WorkerTask {
    uint64_t world_index = 0;
    std::string line;
    /// Worlds the worker may have to simulate before this one (a refined child's lineage): until
    /// it has them, the time limit is that many times longer.
    uint32_t lineage_worlds = 0;
};

/// Worker processes kept from one batch of worlds to the next (a worker keeps the lineages it
/// simulated, so refining one of its worlds again does not start over).
class WorkerPool {
public:
    explicit WorkerPool(SupervisedRun run);
    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Runs `tasks`, appending their records to `writer` in the order of `tasks` whichever worker
    /// finishes first (a reorder window), so that a re-run writes the same file.
    /// Setting `cancel` stops every worker at once; finished worlds stay stored. When a worker
    /// refuses a task (its parent does not come out as stored, or the refinement does not fit
    /// it), no further task is handed out and refusal() says why.
    SamplingStatistics run(const std::vector<WorkerTask>& tasks, LibraryWriter& writer,
                           const SupervisedWorldSink& on_world, const std::atomic<bool>& cancel);
    struct Refusal {
        bool not_reproduced = false;  ///< else: the refinement does not fit the world
        std::string message;          ///< empty: nothing was refused
    };
    const Refusal& refusal() const;

private:
    class Supervisor;
    std::unique_ptr<Supervisor> supervisor_;
};

/// Samples `worlds` with the workers of `run` (see WorkerPool::run).
SamplingStatistics sample_supervised(const SupervisedRun& run, const std::vector<uint64_t>& worlds,
                                     LibraryWriter& writer, const SupervisedWorldSink& on_world,
                                     const std::atomic<bool>& cancel);

/// The worlds of a refinement or a goal search, each in a worker process reading the library
/// (`mwb-engine worker --library PATH`); see WorldMaker.
class SupervisedWorlds : public WorldMaker {
public:
    explicit SupervisedWorlds(SupervisedRun run) : pool_(std::move(run)) {}

    SamplingStatistics sample(const CompiledScene& sampled, uint64_t base_seed, const std::vector<uint64_t>& indices,
                              LibraryWriter& writer, const MadeWorldSink& on_world, SamplingProgress* progress) override;
    SamplingStatistics refine(const CompiledScene& scene, uint64_t base_seed, const RefinementJob& job,
                              LibraryWriter& writer, const MadeWorldSink& on_world, SamplingProgress* progress) override;

private:
    const std::atomic<bool>& cancel_of(const SamplingProgress* progress) const;

    WorkerPool pool_;
    std::atomic<bool> never_cancelled_{false};
};

}  // namespace mwb
