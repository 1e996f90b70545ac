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
/// WorkerRecordHeader::type of a job the worker refuses; the payload is the message, the version
/// one of WorkerRefusal. Never a library record type.
constexpr uint32_t kWorkerRefusal = 0xFFFFFFFFu;
enum class WorkerRefusal : uint32_t {
    NotReproduced = 0,  ///< the world it refines does not come out as stored
    DoesNotFit = 1,     ///< the refinement does not fit that world
};
/// WorkerRecordHeader::type a worker sends (no payload) once it has the lineage of the world a
/// refinement job refines, before it simulates the child: the child's own time starts there.
constexpr uint32_t kWorkerLineageReady = 0xFFFFFFFEu;
/// WorkerRecordHeader::type a worker sends before a world's record when ODE gave messages while
/// it stepped; the payload is encode_ode_messages (sim/OdeMessages.h).
constexpr uint32_t kWorkerOdeMessages = 0xFFFFFFFDu;

/// Reads jobs (engine/WorkerJob.h), one per line, on its job channel (WorkerProcess.h) until it
/// ends; simulates each and writes its record to the record channel as a WorkerRecordHeader
/// followed by the payload.
/// With options.library_path the run is that library's (sampled worlds and refined children);
/// otherwise it is the sampling run of `options` (scene, seed, parameters, bounds), sampled
/// worlds only. Returns the exit code.
int run_world_worker(const EngineOptions& options);

}  // namespace mwb
