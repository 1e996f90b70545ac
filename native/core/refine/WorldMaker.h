#pragma once
// Who simulates the worlds a refinement or a goal search adds to a library. InProcessWorlds runs
// them on this process's threads; the engine's SupervisedWorlds (engine/SupervisedSampler.h) runs
// each in a worker process, so that a world that makes ODE abort, crash or hang cannot end a search.
// Either way a world is the same pure function of (scene, run, lineage, index): the library
// gets the same records.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "library/LibraryWriter.h"
#include "refine/LineageCache.h"
#include "refine/RefineError.h"
#include "sampler/Sampler.h"
#include "sim/CompiledScene.h"

namespace mwb {

/// The children of one refinement of a stored world, with what re-simulating its lineage needs.
struct RefinementJob {
    uint64_t parent_world = 0;
    uint64_t root_world = 0;
    std::vector<RefineStep> lineage{};  ///< the parent's refinements, oldest first
    /// What the parent stored, to check that its lineage comes out as stored.
    uint32_t parent_frames = 0;
    uint64_t parent_contacts = 0;
    std::string library_build;          ///< the engine build that made the library (for messages)
    /// The children's scene is not the one the library's worlds were refined in so far (bodies
    /// added or removed): worlds kept from earlier refinements must not be reused.
    bool scene_changed = false;
    std::vector<RefineStep> children{};
};

/// Called after each world's record was appended; `reason` says why a rejected one was rejected.
using MadeWorldSink = std::function<void(uint64_t world_index, bool stored, const std::string& reason)>;

class WorldMaker {
public:
    virtual ~WorldMaker() = default;
    /// Samples worlds `indices` of the run (`sampled`: the scene as sampled) into `writer`.
    virtual SamplingStatistics sample(const CompiledScene& sampled, uint64_t base_seed,
                                      const std::vector<uint64_t>& indices, LibraryWriter& writer,
                                      const MadeWorldSink& on_world, SamplingProgress* progress) = 0;
    /// Simulates the children of `job` in `scene` (the library's scene now) into `writer`. Throws
    /// WorldNotReproduced, before appending anything, when the parent does not come out as stored.
    virtual SamplingStatistics refine(const CompiledScene& scene, uint64_t base_seed, const RefinementJob& job,
                                      LibraryWriter& writer, const MadeWorldSink& on_world,
                                      SamplingProgress* progress) = 0;
};

/// The exact lineage of the world `job` refines: from `cache` as far as it keeps it, simulated
/// for the rest (and kept there). Throws WorldNotReproduced when it does not come out as stored.
std::vector<WorldResult> exact_lineage(const CompiledScene& scene, uint64_t base_seed, const RefinementJob& job,
                                       LineageCache* cache);

/// Worlds simulated on this process's threads, the lineages it made kept for the next refinement.
class InProcessWorlds : public WorldMaker {
public:
    /// `also` (optional) sees each finished world, after its record was appended.
    explicit InProcessWorlds(int threads, size_t cache_bytes = 0, WorldSink also = {})
        : threads_(threads), cache_(cache_bytes), also_(std::move(also)) {}

    SamplingStatistics sample(const CompiledScene& sampled, uint64_t base_seed, const std::vector<uint64_t>& indices,
                              LibraryWriter& writer, const MadeWorldSink& on_world, SamplingProgress* progress) override;
    SamplingStatistics refine(const CompiledScene& scene, uint64_t base_seed, const RefinementJob& job,
                              LibraryWriter& writer, const MadeWorldSink& on_world, SamplingProgress* progress) override;

private:
    WorldSink appending(LibraryWriter& writer, const MadeWorldSink& on_world, bool keep);

    int threads_;
    LineageCache cache_;
    WorldSink also_;
};

}  // namespace mwb
