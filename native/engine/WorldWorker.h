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
/// WorkerRecordHeader::type of a job the worker refuses (the world it refines does not come out
/// as stored); the payload is the message. Never a library record type.
constexpr uint32_t kWorkerRefusal = 0xFFFFFFFFu;

/// Reads jobs (engine/WorkerJob.h), one per line, on standard input until it ends; simulates each
/// and writes its record to standard output as a WorkerRecordHeader followed by the payload.
/// With options.library_path the run is that library's (sampled worlds and refined children);
/// otherwise it is the sampling run of `options` (scene, seed, parameters, bounds), sampled
/// worlds only. Returns the exit code.
int run_world_worker(const EngineOptions& options);

}  // namespace mwb
