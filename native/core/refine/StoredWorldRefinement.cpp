#include "refine/StoredWorldRefinement.h"

#include <algorithm>
#include <cmath>

#include "common/BuildInfo.h"
#include "library/LibraryFormat.h"
#include "library/SceneRevision.h"
#include "scene/BodyChanges.h"
#include "scene/SceneJson.h"
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

const StoredWorld& find_world(const LibraryReader& reader, uint64_t world_index) {
    for (const StoredWorld& w : reader.worlds())
        if (w.world_index == world_index) return w;
    throw RefineError("no world " + std::to_string(world_index) + " in " + reader.path());
}

// The library's scene as the children see it, with the bodies they gain and lose.
struct SceneChange {
    Scene scene;
    bool grew = false;  ///< bodies were appended: a scene revision must be stored first
    std::vector<uint32_t> added{}, removed{};
};

SceneChange change_scene(const LibraryReader& reader, const StoredWorld& parent, const RefineRequest& request) {
    SceneChange change{scene_from_json(reader.scene_json())};
    if (request.add.empty() && request.remove.empty() && request.update.empty()) return change;
    std::vector<uint8_t> present(change.scene.bodies.size(), 0);
    for (size_t i = 0; i < parent.tracks.size() && i < present.size(); ++i) present[i] = parent.tracks[i].present;
    try {
        const BodyChanges changes =
            change_bodies(change.scene, present, request.source_scene, request.add, request.remove, request.update);
        change.added = changes.added;
        change.removed = changes.removed;
        change.grew = changes.scene_grew;
    } catch (const SceneChangeError& error) {
        std::string message = error.what();
        std::replace(message.begin(), message.end(), '\n', ';');
        throw RefineError("world " + std::to_string(parent.world_index) + ": " + message);
    }
    return change;
}

}  // namespace

RefineOutcome refine_stored_world(const LibraryReader& reader, const RefineRequest& request, LibraryWriter& writer,
                                  const WorldSink& on_world, SamplingProgress* progress, LineageCache* cache) {
    const RunHeader& header = reader.header();
    const StoredWorld& parent = find_world(reader, request.parent_world);
    SceneChange change = change_scene(reader, parent, request);
    const size_t sampled_bodies = scene_from_json(header.scene_json).bodies.size();
    const std::string scene_now = change.grew ? scene_to_json(change.scene) : std::string();
    const CompiledScene compiled(std::move(change.scene), header.parameters, sampled_bodies);

    // The lineage is re-simulated exactly; a world that does not come out as stored was made by
    // another engine build, and refining it would give children of a different parent.
    const uint64_t root = parent.lineage.empty() ? parent.world_index : parent.root_world;
    // Worlds made in this process came out of this build: a kept lineage needs no check.
    const bool same_scene = !change.grew && change.added.empty() && change.removed.empty();
    std::vector<WorldResult> chain;
    if (cache && same_scene) chain = cache->chain(root, parent.lineage);
    if (chain.empty()) {
        chain = simulate_lineage(compiled, header.base_seed, root, parent.lineage);
        if (chain.back().frame_count != parent.frame_count || chain.back().contacts.size() != parent.contacts.size())
            throw WorldNotReproduced(not_reproduced_message(parent.world_index, header.engine_build));
        if (cache && same_scene)
            for (const WorldResult& w : chain) cache->keep(w);
    }

    RefineOutcome outcome;
    const bool changes_scene = !change.added.empty() || !change.removed.empty();
    outcome.branch_frame = changes_scene || request.branch_time_s <= 0
                               ? 0
                               : static_cast<uint64_t>(std::floor(request.branch_time_s * header.parameters.record_hz));
    outcome.first_child = request.first_child >= 0 ? static_cast<uint64_t>(request.first_child) : reader.next_world_index();
    outcome.added = change.added;
    outcome.removed = change.removed;
    std::vector<RefineStep> children;
    for (uint64_t k = 0; k < request.count; ++k)
        children.push_back({outcome.branch_frame * compiled.steps_per_frame(), outcome.first_child + k, request.bodies,
                            change.added, change.removed});
    if (children.empty()) throw RefineError("nothing to refine: the count of new worlds is 0");
    try {
        check_refinement(compiled, chain, children.front());
    } catch (const std::invalid_argument& error) {
        throw RefineError(error.what());
    }
    if (change.grew)
        writer.append_record(kRecordTypeSceneRevision, kSceneRevisionRecordVersion,
                             encode_scene_revision({reader.scene_revision() + 1, scene_now}));
    outcome.statistics = refine_worlds(compiled, header.base_seed, chain, children, request.threads,
                                       [&](WorldResult&& world) {
                                           writer.append(world);
                                           if (cache && same_scene) cache->keep(world);
                                           if (on_world) on_world(std::move(world));
                                       },
                                       progress);
    return outcome;
}

}  // namespace mwb
