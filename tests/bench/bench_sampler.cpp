// Sampler benchmarks: our per-world overhead against bare ODE stepping of the same scene, and
// the parallel speed-up. Both measured side by side in one run.
#include <omp.h>

#include <algorithm>
#include <vector>

#include "BenchReport.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "sim/BodyInitialState.h"
#include "sim/OdeRandom.h"
#include "sim/OdeWorld.h"
#include "sim/WorldSimulator.h"

namespace mwb::bench {
namespace {

struct BareContext {
    dWorldID world;
    dJointGroupID contacts;
};

// ODE's textbook near callback: what a plain ODE program does every step.
void bare_near_callback(void* data, dGeomID a, dGeomID b) {
    auto* context = static_cast<BareContext*>(data);
    dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (ba == bb) return;
    dContactGeom geoms[8];
    const int n = dCollide(a, b, 8, geoms, sizeof(dContactGeom));
    for (int k = 0; k < n; ++k) {
        dContact contact{};
        contact.surface.mode = dContactApprox1;
        contact.surface.mu = 0.25;
        contact.geom = geoms[k];
        dJointAttach(dJointCreateContact(context->world, context->contacts, &contact), ba, bb);
    }
}

// Bare ODE: the same bodies and initial states, stepped `steps` times with no recording,
// impact detection, perturbation or checkpoints.
double bare_ode_seconds(const CompiledScene& compiled, uint64_t world_index, uint64_t steps) {
    PortableRandom initial(derive_stream_seed(derive_world_seed(1, world_index), kInitialStateStream));
    OdeWorld world(compiled, draw_initial_states(compiled.scene(), initial));
    BareContext context{world.world(), world.contact_group()};
    // A plain ODE program keeps its geoms in a space; the engine's are in none.
    const dSpaceID space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
    dSpaceSetCleanup(space, 0);
    for (dGeomID geom : world.geoms()) dSpaceAdd(space, geom);
    uint64_t ode_random = 0;
    OdeRandomScope scope(ode_random);
    const auto start = std::chrono::steady_clock::now();
    for (uint64_t s = 0; s < steps; ++s) {
        dSpaceCollide(space, &context, bare_near_callback);
        dWorldQuickStep(world.world(), compiled.physics_dt_s());
        dJointGroupEmpty(world.contact_group());
    }
    const double seconds = seconds_since(start);
    dSpaceDestroy(space);
    return seconds;
}

double sample_seconds(const CompiledScene& compiled, uint64_t count, int threads) {
    const auto start = std::chrono::steady_clock::now();
    sample_worlds(compiled, 1, 0, count, threads, [](WorldResult&&) {});
    return seconds_since(start);
}

}  // namespace
}  // namespace mwb::bench

int main() {
    using namespace mwb;
    using namespace mwb::bench;
    initialize_ode_once();
    std::printf("Sampler, 50-box pile (tests/bench/pile50.json), %d cores\n", omp_get_num_procs());
    CompiledScene compiled(load_scene_file(data_path("pile50.json")), SimulationParameters{});
    const uint64_t worlds = 8;
    double ours = 0, bare = 0;
    for (uint64_t k = 0; k < worlds; ++k) {
        const auto start = std::chrono::steady_clock::now();
        const WorldResult w = simulate_world(compiled, 1, k);
        ours += seconds_since(start);
        const uint64_t steps = static_cast<uint64_t>(std::llround(w.simulated_time_s * compiled.step_hz()));
        bare += bare_ode_seconds(compiled, k, steps);
    }
    report("sampler_overhead_ratio", ours / bare, "x", "ours / bare ODE, same steps, 1 thread (target <= 1.10)");
    const uint64_t parallel_worlds = 16;
    const double one = sample_seconds(compiled, parallel_worlds, 1);
    const double two = sample_seconds(compiled, parallel_worlds, 2);
    report("parallel_speedup_2t", one / two, "x", "worlds/s on 2 threads / 1 thread (target >= 1.8)");
    report("worlds_per_min_50body", 60.0 * parallel_worlds / two, "worlds/min", "2 threads, 5 s worlds ending at rest");
    return 0;
}
