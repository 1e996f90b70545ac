#include "refine/StoredWorldRefinement.h"

#include <algorithm>
#include <cmath>

#include "library/LibraryFormat.h"
#include "library/SceneRevision.h"
#include "scene/BodyChanges.h"
#include "scene/SceneJson.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

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
                                  WorldMaker& maker, const MadeWorldSink& on_world, SamplingProgress* progress) {
    const RunHeader& header = reader.header();
    const StoredWorld& parent = find_world(reader, request.parent_world);
    SceneChange change = change_scene(reader, parent, request);
    const size_t sampled_bodies = scene_from_json(header.scene_json).bodies.size();
    const std::string scene_now = change.grew ? scene_to_json(change.scene) : std::string();
    const CompiledScene compiled(std::move(change.scene), header.parameters, sampled_bodies);

    RefineOutcome outcome;
    const bool changes_scene = !change.added.empty() || !change.removed.empty();
    outcome.branch_frame = changes_scene || request.branch_time_s <= 0
                               ? 0
                               : static_cast<uint64_t>(std::floor(request.branch_time_s * header.parameters.record_hz));
    outcome.first_child = request.first_child >= 0 ? static_cast<uint64_t>(request.first_child) : reader.next_world_index();
    outcome.added = change.added;
    outcome.removed = change.removed;
    // The lineage is re-simulated exactly (by the maker); a world that does not come out as
    // stored was made by another engine build, and refining it would give children of another
    // parent.
    RefinementJob job{parent.world_index, parent.lineage.empty() ? parent.world_index : parent.root_world,
                      parent.lineage, parent.frame_count, parent.contacts.size(), header.engine_build,
                      change.grew || changes_scene, {}};
    for (uint64_t k = 0; k < request.count; ++k)
        job.children.push_back({outcome.branch_frame * compiled.steps_per_frame(), outcome.first_child + k,
                                request.bodies, change.added, change.removed});
    if (job.children.empty()) throw RefineError("nothing to refine: the count of new worlds is 0");
    RefinedParent refined{parent.world_index, parent.frame_count, std::vector<uint8_t>(compiled.bodies().size(), 0)};
    for (size_t i = 0; i < parent.tracks.size() && i < refined.present.size(); ++i)
        refined.present[i] = parent.tracks[i].present;
    try {
        check_refinement(compiled, refined, job.children.front());
    } catch (const std::invalid_argument& error) {
        throw RefineError(error.what());
    }
    if (change.grew) {
        // The revision must be in the file before the children; check first that the parent
        // reproduces, so that a refused request still writes nothing.
        exact_lineage(compiled, header.base_seed, job, nullptr);
        writer.append_record(kRecordTypeSceneRevision, kSceneRevisionRecordVersion,
                             encode_scene_revision({reader.scene_revision() + 1, scene_now}));
    }
    try {
        outcome.statistics = maker.refine(compiled, header.base_seed, job, writer, on_world, progress);
    } catch (const std::invalid_argument& error) {
        throw RefineError(error.what());  // the simulated parent refuses what its record allowed
    }
    return outcome;
}

RefineOutcome refine_stored_world(const LibraryReader& reader, const RefineRequest& request, LibraryWriter& writer,
                                  const WorldSink& on_world, SamplingProgress* progress) {
    InProcessWorlds maker(request.threads, 0, on_world);
    return refine_stored_world(reader, request, writer, maker, {}, progress);
}

}  // namespace mwb
