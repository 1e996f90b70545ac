// Refinement benchmarks: a refined world against a full one of the same 50-body scene, and the
// time from a refinement request to the first refined world stored in a library.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "BenchReport.h"
#include "common/BuildInfo.h"
#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "sim/WorldSimulator.h"

int main() {
    using namespace mwb;
    using namespace mwb::bench;
    std::printf("Refinement\n");
    SimulationParameters parameters;
    parameters.stop_at_rest = false;  // the same length for every world compared
    CompiledScene pile(load_scene_file(data_path("pile50.json")), parameters);
    const uint64_t late = static_cast<uint64_t>(std::llround(3.5 * 120)) * pile.steps_per_frame();
    const uint32_t body = 30;  // a box in the middle of the pile
    double full_s = 0, refined_s = 0;
    const int worlds = 4;
    for (int w = 0; w < worlds; ++w) {
        auto start = std::chrono::steady_clock::now();
        const std::vector<WorldResult> chain = simulate_lineage(pile, 1, static_cast<uint64_t>(w), {});
        full_s += seconds_since(start);
        start = std::chrono::steady_clock::now();
        refine_world(pile, 1, chain, {late, 1000 + static_cast<uint64_t>(w), {body}});
        refined_s += seconds_since(start);
    }
    report("refine_speedup_vs_full", refined_s / full_s, "x",
           "time per refined world / per full world; one box refined at 3.5 of 5 s (lower is faster)");

    // Changing the scene after sampling: one ball added, dropped onto the pile, or one box removed;
    // both act from t = 0, so the whole world is re-run, but only what they reach is simulated.
    Scene grown = load_scene_file(data_path("pile50.json"));
    const size_t sampled = grown.bodies.size();
    Body ball;
    ball.name = "AddedBall";
    ball.shape.type = ShapeType::Sphere;
    ball.shape.radius_m = 0.15;
    ball.initial.location = {0.3, 0.3, 4.0};
    grown.bodies.push_back(ball);
    CompiledScene grown_pile(grown, parameters, sampled);
    double full_grown_s = 0, added_s = 0, removed_s = 0;
    double added_changed = 0, removed_changed = 0;  // bodies simulated anew, summed over worlds
    auto changed_count = [](const WorldResult& w) {
        return static_cast<double>(std::count(w.changed.begin(), w.changed.end(), uint8_t{1}));
    };
    for (int w = 0; w < worlds; ++w) {
        auto start = std::chrono::steady_clock::now();
        const std::vector<WorldResult> chain = simulate_lineage(grown_pile, 1, static_cast<uint64_t>(w), {});
        full_grown_s += seconds_since(start);
        start = std::chrono::steady_clock::now();
        added_changed += changed_count(refine_world(
            grown_pile, 1, chain, {0, 2000 + static_cast<uint64_t>(w), {}, {static_cast<uint32_t>(sampled)}, {}}));
        added_s += seconds_since(start);
        start = std::chrono::steady_clock::now();
        removed_changed += changed_count(refine_world(grown_pile, 1, chain, {0, 3000 + static_cast<uint64_t>(w), {}, {}, {body}}));
        removed_s += seconds_since(start);
    }
    report("add_body_speedup_vs_full", added_s / full_grown_s, "x",
           "time per world with one ball added to the 50-box pile / per full world (lower is faster)");
    report("remove_body_speedup_vs_full", removed_s / full_grown_s, "x",
           "time per world with one box of the pile removed / per full world (lower is faster)");
    const auto boxes = std::count_if(grown.bodies.begin(), grown.bodies.begin() + static_cast<std::ptrdiff_t>(sampled),
                                     [](const Body& b) { return b.type == BodyType::Active; });
    std::printf("  bodies simulated anew per world: %.1f with the ball added (ball included), %.1f with a box removed"
                " (the pile has %td boxes)\n",
                added_changed / worlds, removed_changed / worlds, boxes);

    // From the request (library on disk) to the first refined world stored.
    const std::string library = (std::filesystem::temp_directory_path() / "mwb_bench_refine.mwb").string();
    std::filesystem::remove(library);
    const Scene quickstart = load_scene_file(std::string(MWB_BENCH_DIR) + "/../scenes/quickstart.json");
    const RunHeader header{scene_to_json(quickstart), SimulationParameters{}, CodecBounds{}, 1, engine_build()};
    CompiledScene compiled(quickstart, header.parameters);
    {
        LibraryWriter writer(library, header);
        sample_worlds(compiled, 1, 0, 8, 0, [&](WorldResult&& w) { writer.append(w); });
    }
    const auto start = std::chrono::steady_clock::now();
    const LibraryReader reader(library);
    const StoredWorld& parent = reader.worlds()[3];
    const std::vector<WorldResult> chain = simulate_lineage(compiled, 1, parent.world_index, {});
    LibraryWriter writer(library, reader.header());
    writer.append(refine_world(compiled, 1, chain, {120 * compiled.steps_per_frame(), 100, {2}}));
    report("refine_first_world_s", seconds_since(start), "s", "quick-start scene, request to first refined world stored");
    std::filesystem::remove(library);
    return 0;
}
