#pragma once
// Refinement of a world stored in a library: rebuild its exact lineage, check that it reproduces,
// and append children that re-simulate chosen bodies from a branch time, or that add, remove or
// update bodies from t = 0. The engine, the bindings and a search that refines many times in one
// process all call this.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "refine/LineageCache.h"
#include "sampler/Sampler.h"
#include "scene/Scene.h"

namespace mwb {

/// A request that does not fit the library (no such world, a body it lacks, a world that does not
/// reproduce); the message is one line.
struct RefineError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A stored world that does not come out as stored when simulated again: the library was made by
/// another engine build (or is damaged). No refinement of that library can succeed, so callers
/// that try several requests (the goal search) stop on it.
struct WorldNotReproduced : RefineError {
    using RefineError::RefineError;
};

struct RefineRequest {
    uint64_t parent_world = 0;
    /// Scene body indices simulated anew from the branch (with whatever they touch).
    std::vector<uint32_t> bodies{};
    /// Where the children leave the parent, seconds; snapped down to a recorded frame. Changing
    /// the scene (add, remove, update) always branches at 0.
    double branch_time_s = 0;
    uint64_t count = 1;
    /// Index of the first child; < 0: the library's next_world_index().
    int64_t first_child = -1;
    /// Objects to add, remove, or redefine (remove + add); added and updated ones come from
    /// `source_scene` (a newer export of the scene).
    std::vector<std::string> add{}, remove{}, update{};
    Scene source_scene{};
    int threads = 0;  ///< <= 0: all cores
};

struct RefineOutcome {
    SamplingStatistics statistics;
    uint64_t first_child = 0;
    uint64_t branch_frame = 0;             ///< recorded frame the children leave the parent at
    std::vector<uint32_t> added{}, removed{};  ///< scene body indices the children gained and lost
};

/// Refines world `request.parent_world` of the library `reader` has read, appending to `writer`
/// (the same file) a scene revision when the scene grew, then each child as it finishes, in
/// parallel. `on_world` is called after each append, from a worker thread, never concurrently.
/// Throws RefineError before anything is written when the request does not fit. With `cache`, a
/// parent whose lineage it keeps is not re-simulated, and the lineage and children are kept in it.
RefineOutcome refine_stored_world(const LibraryReader& reader, const RefineRequest& request, LibraryWriter& writer,
                                  const WorldSink& on_world = {}, SamplingProgress* progress = nullptr,
                                  LineageCache* cache = nullptr);

}  // namespace mwb
