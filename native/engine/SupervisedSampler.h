#pragma once
// Sampling in worker processes under a supervisor, so that no world can end the run: a world that
// makes ODE abort, crash or hang takes down only its worker. The supervisor stores it as a
// rejection naming the fault, starts a new worker and goes on; every other world is stored exactly
// as an in-process run would store it (a world is a pure function of its index).
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "library/LibraryWriter.h"
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

/// Called in the supervisor's thread after each world's record was appended (or after a world
/// was rejected for a fault); `reason` says why a rejected world was rejected.
using SupervisedWorldSink = std::function<void(uint64_t world_index, bool stored, const std::string& reason)>;

/// Samples `worlds` in worker processes, appending each record to `writer` as it arrives (in
/// completion order). Setting `cancel` stops every worker at once; finished worlds stay stored.
SamplingStatistics sample_supervised(const SupervisedRun& run, const std::vector<uint64_t>& worlds,
                                     LibraryWriter& writer, const SupervisedWorldSink& on_world,
                                     const std::atomic<bool>& cancel);

}  // namespace mwb
