#pragma once
// Refinement of a world stored in a library: rebuild its exact lineage, check that it reproduces,
// and append children that re-simulate chosen bodies from a branch time, or that add, remove or
// update bodies from t = 0. The engine, the bindings and a search that refines many times in one
// process all call this.
#include <cstdint>
#include <string>
#include <vector>

#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "refine/RefineError.h"
#include "refine/WorldMaker.h"
#include "sampler/Sampler.h"
#include "scene/Scene.h"

namespace mwb {

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
/// (the same file) a scene revision when the scene grew, then each child as `maker` finishes it.
/// `on_world` is called after each append, never concurrently. Throws RefineError before
/// anything is written when the request does not fit. A maker that keeps lineages (a search's)
/// does not re-simulate a parent whose lineage it keeps.
RefineOutcome refine_stored_world(const LibraryReader& reader, const RefineRequest& request, LibraryWriter& writer,
                                  WorldMaker& maker, const MadeWorldSink& on_world = {},
                                  SamplingProgress* progress = nullptr);

/// The same on this process's threads (request.threads); `on_world` gets each finished child.
RefineOutcome refine_stored_world(const LibraryReader& reader, const RefineRequest& request, LibraryWriter& writer,
                                  const WorldSink& on_world = {}, SamplingProgress* progress = nullptr);

}  // namespace mwb
