// Sampler benchmarks: our per-world overhead against bare ODE stepping of the same scene, and
// the parallel speed-up. Both measured side by side in one run.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "BenchReport.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "sim/BodyInitialState.h"
#include "sim/BroadPhase.h"
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

void note_pair(void* data, dGeomID a, dGeomID b) {
    // Pairs of two fixed geoms are dropped here, as the engine's broad phase never reports them.
    if (!dGeomGetBody(a) && !dGeomGetBody(b)) return;
    ++*static_cast<size_t*>(data);
}

// The staircase's layout: 99 fixed treads and strings up a helix, 11 moving boxes (a figure's body
// parts) tumbling down it. Seconds for `steps` broad phases by ODE's sweep and prune over every
// geom and by the engine's, side by side; both must find the same number of pairs.
std::pair<double, double> broad_phase_seconds(int steps) {
    dWorldID world = dWorldCreate();
    std::vector<dGeomID> geoms;
    for (int k = 0; k < 99; ++k) {
        const double angle = 0.35 * k, z = 0.1 * k;
        geoms.push_back(dCreateBox(nullptr, k % 3 == 2 ? 0.05 : 1.2, k % 3 == 2 ? 0.05 : 0.4, k % 3 == 2 ? 1.0 : 0.05));
        dGeomSetPosition(geoms.back(), 0.8 * std::cos(angle), 0.8 * std::sin(angle), z);
        dMatrix3 turn;
        dRFromAxisAndAngle(turn, 0, 0, 1, angle);
        dGeomSetRotation(geoms.back(), turn);
    }
    std::vector<dBodyID> parts;
    for (int k = 0; k < 11; ++k) {
        parts.push_back(dBodyCreate(world));
        geoms.push_back(dCreateBox(nullptr, 0.25, 0.15, 0.3));
        dGeomSetBody(geoms.back(), parts.back());
    }
    const auto pose_parts = [&](int step) {
        const double angle = 0.35 * 99 * (1.0 - step / double(steps)), z = 0.1 * 99 * (1.0 - step / double(steps));
        for (size_t k = 0; k < parts.size(); ++k)
            dBodySetPosition(parts[k], 0.8 * std::cos(angle) + 0.1 * k, 0.8 * std::sin(angle), z + 0.3 + 0.05 * k);
    };
    const dSpaceID space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XYZ);
    dSpaceSetCleanup(space, 0);
    for (dGeomID geom : geoms) dSpaceAdd(space, geom);
    size_t ode_pairs = 0, our_pairs = 0;
    auto start = std::chrono::steady_clock::now();
    for (int step = 0; step < steps; ++step) {
        pose_parts(step);
        dSpaceCollide(space, &ode_pairs, note_pair);
    }
    const double ode = seconds_since(start);
    dSpaceDestroy(space);
    BroadPhase broad_phase;
    std::vector<GeomPair> found;
    start = std::chrono::steady_clock::now();
    for (int step = 0; step < steps; ++step) {
        pose_parts(step);
        broad_phase.find_pairs(geoms, found);
        our_pairs += found.size();
    }
    const double ours = seconds_since(start);
    if (ode_pairs != our_pairs || our_pairs == 0)
        std::printf("  broad phases disagree: ODE %zu pairs, ours %zu\n", ode_pairs, our_pairs);
    for (dGeomID geom : geoms) dGeomDestroy(geom);
    dWorldDestroy(world);
    return {ode, ours};
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
    const auto [ode_sweep_s, engine_sweep_s] = broad_phase_seconds(20000);
    report("broad_phase_speedup_staircase", ode_sweep_s / engine_sweep_s, "x",
           "ODE's sweep over every geom / the engine's broad phase, 99 fixed and 11 moving geoms");
    return 0;
}
