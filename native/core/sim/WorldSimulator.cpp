#include "sim/WorldSimulator.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "sim/OdeWorld.h"
#include "sim/PortableRandom.h"
#include "sim/WorldRun.h"

namespace mwb {
namespace {

template <typename T>
void hash_bytes(uint64_t& h, const T* data, size_t count) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(data);
    for (size_t i = 0; i < count * sizeof(T); ++i) {
        h ^= bytes[i];
        h *= 0x100000001B3ull;
    }
}

}  // namespace

WorldResult simulate_world(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                           const std::atomic<bool>* cancel) {
    try {
        WorldRun run(compiled, base_seed, world_index);
        return run.run(cancel);
    } catch (const OdeError& error) {
        WorldResult result;
        result.world_index = world_index;
        result.seed = derive_world_seed(base_seed, world_index);
        result.status = WorldStatus::Rejected;
        result.reject_reason = error.what();
        return result;
    }
}

WorldResult resume_world(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                         const Checkpoint& checkpoint, const std::atomic<bool>* cancel) {
    WorldRun run(compiled, base_seed, world_index);
    run.restore(checkpoint);
    return run.run(cancel);
}

namespace {

// Runs the lineage `steps` (each replaying its own parent world) from the original world's last
// checkpoint before the first branch. A step that branches no later than an earlier one
// supersedes it: the earlier switch never happens in this run.
WorldResult run_refinements(const CompiledScene& compiled, uint64_t base_seed, const std::vector<WorldResult>& chain,
                            const std::vector<RefineStep>& steps, const std::atomic<bool>* cancel) {
    std::vector<RefineStep> effective;
    std::vector<const WorldResult*> parents;
    for (size_t k = steps.size(); k-- > 0;) {
        if (!effective.empty() && steps[k].branch_step >= effective.front().branch_step) continue;
        effective.insert(effective.begin(), steps[k]);
        parents.insert(parents.begin(), &chain[k]);
    }
    const WorldResult& root = chain.front();
    WorldRun run(compiled, base_seed, root.world_index, steps);
    const Checkpoint* start = nullptr;
    for (const Checkpoint& c : root.checkpoints)
        if (c.step_index <= effective.front().branch_step) start = &c;
    // From t = 0 (always so when the lineage adds or removes bodies) the run starts afresh: a
    // sampled checkpoint would overwrite the starting state of added bodies.
    if (start && start->step_index > 0) run.restore(*start);
    run.plan_refinements(effective, parents);
    WorldResult result = run.run(cancel);
    result.lineage = steps;
    result.root_world = root.world_index;
    return result;
}

}  // namespace

void check_refinement(const CompiledScene& compiled, const std::vector<WorldResult>& chain, const RefineStep& step) {
    if (chain.empty()) throw std::invalid_argument("refinement needs the world to refine");
    const WorldResult& parent = chain.back();
    if (parent.status != WorldStatus::Ok || parent.first_frame != 0)
        throw std::invalid_argument("refinement needs a complete, valid parent world");
    if (chain.size() != parent.lineage.size() + 1)
        throw std::invalid_argument("the chain does not match the parent's lineage");
    check_refinement(compiled, RefinedParent{parent.world_index, parent.frame_count, parent.present}, step);
}

void check_refinement(const CompiledScene& compiled, const RefinedParent& parent, const RefineStep& step) {
    if (step.branch_step % compiled.steps_per_frame() != 0 ||
        step.branch_step / compiled.steps_per_frame() >= parent.frame_count)
        throw std::invalid_argument("branch step " + std::to_string(step.branch_step) + " is not a frame of the parent");
    const bool changes_scene = !step.added.empty() || !step.removed.empty();
    if (step.bodies.empty() && !changes_scene)
        throw std::invalid_argument("refinement needs at least one body to refine, add or remove");
    if (changes_scene && step.branch_step != 0)
        throw std::invalid_argument("bodies are added and removed from t = 0 only");
    const size_t n = compiled.bodies().size();
    auto in_parent = [&](uint32_t body) { return parent.present.empty() || parent.present[body]; };
    auto name = [&](uint32_t body) { return "body '" + compiled.scene().bodies[body].name + "'"; };
    for (uint32_t body : step.bodies) {
        if (body >= n || !compiled.bodies()[body].dynamic)
            throw std::invalid_argument("body " + std::to_string(body) + " is not a simulated body");
        if (!in_parent(body)) throw std::invalid_argument(name(body) + " is not in world " + std::to_string(parent.world_index));
    }
    for (uint32_t body : step.removed) {
        if (body >= n) throw std::invalid_argument("body " + std::to_string(body) + " is not in the scene");
        if (!in_parent(body)) throw std::invalid_argument(name(body) + " is not in world " + std::to_string(parent.world_index));
    }
    for (uint32_t body : step.added) {
        if (body >= n) throw std::invalid_argument("body " + std::to_string(body) + " is not in the scene");
        if (in_parent(body)) throw std::invalid_argument(name(body) + " is already in world " + std::to_string(parent.world_index));
        if (std::count(step.added.begin(), step.added.end(), body) > 1 ||
            std::count(step.removed.begin(), step.removed.end(), body) > 0)
            throw std::invalid_argument(name(body) + " is listed twice");
    }
}

WorldResult refine_world(const CompiledScene& compiled, uint64_t base_seed, const std::vector<WorldResult>& chain,
                         const RefineStep& step, const std::atomic<bool>* cancel) {
    check_refinement(compiled, chain, step);
    std::vector<RefineStep> steps = chain.back().lineage;
    steps.push_back(step);
    return run_refinements(compiled, base_seed, chain, steps, cancel);
}

std::vector<WorldResult> simulate_lineage(const CompiledScene& compiled, uint64_t base_seed, uint64_t root_world,
                                          const std::vector<RefineStep>& lineage, const std::atomic<bool>* cancel) {
    std::vector<WorldResult> chain;
    chain.push_back(simulate_world(compiled, base_seed, root_world, cancel));
    for (const RefineStep& step : lineage) {
        WorldResult next = refine_world(compiled, base_seed, chain, step, cancel);
        chain.push_back(std::move(next));
    }
    return chain;
}

uint64_t hash_world(const WorldResult& world) {
    uint64_t h = 0xCBF29CE484222325ull;
    hash_bytes(h, &world.frame_count, 1);
    hash_bytes(h, world.positions_m.data(), world.positions_m.size());
    hash_bytes(h, world.orientations.data(), world.orientations.size());
    for (const ContactEvent& e : world.contacts) {
        hash_bytes(h, &e.time_s, 1);
        hash_bytes(h, &e.body, 1);
        hash_bytes(h, &e.other, 1);
        hash_bytes(h, &e.impulse_ns, 1);
    }
    hash_bytes(h, world.rest_time_s.data(), world.rest_time_s.size());
    for (const Checkpoint& c : world.checkpoints) {
        hash_bytes(h, &c.step_index, 1);
        for (const BodyState& s : c.bodies) {
            hash_bytes(h, s.position_m.data(), 3);
            hash_bytes(h, s.orientation.data(), 4);
            hash_bytes(h, s.linear_velocity.data(), 3);
            hash_bytes(h, s.angular_velocity.data(), 3);
        }
        hash_bytes(h, &c.ode_random_state, 1);
        hash_bytes(h, c.perturbation_random_state.data(), 4);
    }
    return h;
}

}  // namespace mwb
