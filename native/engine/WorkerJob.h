#pragma once
// What a supervisor hands a worker process, one line per world: a sampled world's index, or one
// child of a refinement with the lineage of the world it refines.
#include <cstdint>
#include <string>

#include "refine/WorldMaker.h"

namespace mwb {

struct WorkerJob {
    uint64_t world_index = 0;
    bool refined = false;
    RefinementJob refinement{};  ///< refined: the job, with the one child to simulate
};

std::string sampled_world_line(uint64_t world_index);
std::string refined_child_line(const RefinementJob& job, size_t child);
/// Throws std::invalid_argument for a line no supervisor writes.
WorkerJob parse_worker_line(const std::string& line);

}  // namespace mwb
