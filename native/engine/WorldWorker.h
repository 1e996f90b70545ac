#pragma once
// The worker side of supervised sampling (see SupervisedSampler.h): a child process of the engine
// that simulates the worlds it is handed, one at a time, so that a world that crashes ODE takes
// only its own process down.
#include <cstdint>
#include <string>
#include <vector>

#include "EngineOptions.h"

namespace mwb {

/// One finished world as a worker sends it: the library record, ready to append.
struct WorkerRecordHeader {
    uint64_t world_index = 0;
    uint32_t type = 0;
    uint32_t version = 0;
    uint32_t size = 0;  ///< payload bytes that follow
};
constexpr size_t kWorkerRecordHeaderBytes = 20;

/// Reads world indices, one decimal number per line, on standard input until it ends; simulates
/// each with the run of `options` (scene, seed, parameters, bounds) and writes its record to
/// standard output as a WorkerRecordHeader followed by the payload. Returns the exit code.
int run_world_worker(const EngineOptions& options);

}  // namespace mwb
