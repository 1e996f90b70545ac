#include "refine/WorldMaker.h"

#include "common/BuildInfo.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

std::string not_reproduced_message(uint64_t world, const std::string& recorded_build) {
    const std::string head = "world " + std::to_string(world) + " does not come out as stored: ";
    if (recorded_build == engine_build())
        return head + "the library was sampled by this same engine build (" + engine_build() +
               "), so the file may be damaged; sample the world again";
    return head + "the library was sampled by " + describe_build(recorded_build) + ", this engine is " +
           engine_build() + "; refine with the engine that sampled it, or sample again with this one";
}

}  // namespace

std::vector<WorldResult> exact_lineage(const CompiledScene& scene, uint64_t base_seed, const RefinementJob& job,
                                       LineageCache* cache) {
    const bool reuse = cache && !job.scene_changed;
    std::vector<WorldResult> chain;
    if (reuse) chain = cache->kept_start(job.root_world, job.lineage);
    // Worlds made in this process came out of this build: only what is simulated now is checked.
    const bool simulated = chain.size() < job.lineage.size() + 1;
    if (chain.empty()) chain.push_back(simulate_world(scene, base_seed, job.root_world));
    while (chain.size() < job.lineage.size() + 1) {
        if (chain.back().status != WorldStatus::Ok) break;
        chain.push_back(refine_world(scene, base_seed, chain, job.lineage[chain.size() - 1]));
    }
    if (simulated && (chain.size() != job.lineage.size() + 1 || chain.back().status != WorldStatus::Ok ||
                      chain.back().frame_count != job.parent_frames ||
                      chain.back().contacts.size() != job.parent_contacts))
        throw WorldNotReproduced(not_reproduced_message(job.parent_world, job.library_build));
    if (reuse)
        for (const WorldResult& w : chain) cache->keep(w);
    return chain;
}

WorldSink InProcessWorlds::appending(LibraryWriter& writer, const MadeWorldSink& on_world, bool keep) {
    return [this, &writer, &on_world, keep](WorldResult&& world) {
        writer.append(world);
        if (keep) cache_.keep(world);
        if (on_world && world.status != WorldStatus::Cancelled)
            on_world(world.world_index, world.status == WorldStatus::Ok, world.reject_reason);
        if (also_) also_(std::move(world));
    };
}

SamplingStatistics InProcessWorlds::sample(const CompiledScene& sampled, uint64_t base_seed,
                                           const std::vector<uint64_t>& indices, LibraryWriter& writer,
                                           const MadeWorldSink& on_world, SamplingProgress* progress) {
    return sample_world_list(sampled, base_seed, indices, threads_, appending(writer, on_world, true), progress);
}

SamplingStatistics InProcessWorlds::refine(const CompiledScene& scene, uint64_t base_seed, const RefinementJob& job,
                                           LibraryWriter& writer, const MadeWorldSink& on_world,
                                           SamplingProgress* progress) {
    const std::vector<WorldResult> chain = exact_lineage(scene, base_seed, job, &cache_);
    return refine_worlds(scene, base_seed, chain, job.children, threads_,
                         appending(writer, on_world, !job.scene_changed), progress);
}

}  // namespace mwb
