#include "sim/SharedPrefix.h"

#include <algorithm>
#include <cmath>

#include "sim/OdeWorld.h"
#include "sim/PortableRandom.h"
#include "sim/WorldRun.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

bool single_value(const Vec3& lo, const Vec3& hi) { return lo == hi; }

bool does_not_vary(const VariationRanges& v) {
    return single_value(v.location_min_m, v.location_max_m) && single_value(v.rotation_min_rad, v.rotation_max_rad) &&
           single_value(v.linear_velocity_min, v.linear_velocity_max) &&
           single_value(v.angular_velocity_min, v.angular_velocity_max) && v.mass_scale_min == v.mass_scale_max &&
           v.friction_scale_min == v.friction_scale_max && v.restitution_scale_min == v.restitution_scale_max;
}

PortableRandom::State initial_perturbation_state(uint64_t base_seed, uint64_t world_index) {
    return PortableRandom(derive_stream_seed(derive_world_seed(base_seed, world_index), kPerturbationStream)).state();
}

}  // namespace

bool worlds_start_alike(const CompiledScene& compiled) {
    const auto& bodies = compiled.scene().bodies;
    const size_t sampled = std::min(compiled.sampled_body_count(), bodies.size());
    for (size_t i = 0; i < sampled; ++i)
        if (!does_not_vary(bodies[i].variation)) return false;
    return true;
}

PrefixSharingSimulator::PrefixSharingSimulator(const CompiledScene& compiled, uint64_t base_seed, bool share)
    : compiled_(compiled), base_seed_(base_seed), share_(share && worlds_start_alike(compiled)) {}

WorldResult PrefixSharingSimulator::simulate(uint64_t world_index, const std::atomic<bool>* cancel) {
    if (!branch_) {
        WorldResult world = simulate_world(compiled_, base_seed_, world_index, cancel);
        // Worlds that start alike all have their first impact at the same step: one complete
        // world tells whether there is a prefix worth sharing.
        if (share_ && world.status == WorldStatus::Ok) {
            keep_prefix_of(world);
            share_ = branch_.has_value();
        }
        return world;
    }
    // Until its first perturbed impact a world has drawn nothing from its perturbation stream, so
    // at the branch its generator is still in its initial state.
    Checkpoint start = *branch_;
    start.perturbation_random_state = initial_perturbation_state(base_seed_, world_index);
    WorldResult world;
    try {
        WorldRun run(compiled_, base_seed_, world_index);
        run.restore(start);
        world = run.run(cancel);
    } catch (const OdeError& error) {
        world = WorldResult{};
        world.world_index = world_index;
        world.seed = derive_world_seed(base_seed_, world_index);
        world.status = WorldStatus::Rejected;
        world.reject_reason = error.what();
        return world;
    }
    splice_prefix(world);
    return world;
}

void PrefixSharingSimulator::keep_prefix_of(const WorldResult& source) {
    // Every impact perturbs (or, with perturbation off, none does and all worlds are the same):
    // the first recorded impact is the first draw. Its step ends at contacts.front().time_s.
    const uint64_t end_step = compiled_.total_steps() + 1;
    const uint64_t first_draw_step =
        source.contacts.empty() ? end_step
                                : static_cast<uint64_t>(std::llround(source.contacts.front().time_s * compiled_.step_hz())) - 1;
    const Checkpoint* branch = nullptr;
    for (const Checkpoint& c : source.checkpoints)
        if (c.step_index <= first_draw_step) branch = &c;
    if (!branch || branch->step_index == 0) return;
    const uint32_t frames = static_cast<uint32_t>(branch->step_index / compiled_.steps_per_frame());
    if (frames > source.frame_count) return;
    const size_t n = source.body_count;
    prefix_frames_ = frames;
    prefix_positions_m_.resize(n * frames * 3);
    prefix_orientations_.resize(n * frames * 4);
    for (size_t i = 0; i < n; ++i) {
        std::copy_n(&source.positions_m[i * source.frame_count * 3], frames * 3, &prefix_positions_m_[i * frames * 3]);
        std::copy_n(&source.orientations[i * source.frame_count * 4], frames * 4, &prefix_orientations_[i * frames * 4]);
    }
    prefix_checkpoints_.clear();
    for (const Checkpoint& c : source.checkpoints)
        if (c.step_index < branch->step_index) prefix_checkpoints_.push_back(c);
    branch_ = *branch;
}

void PrefixSharingSimulator::splice_prefix(WorldResult& resumed) const {
    const size_t n = resumed.body_count;
    const size_t head = prefix_frames_, own = resumed.frame_count, frames = head + own;
    std::vector<double> positions(n * frames * 3), orientations(n * frames * 4);
    for (size_t i = 0; i < n; ++i) {
        std::copy_n(&prefix_positions_m_[i * head * 3], head * 3, &positions[i * frames * 3]);
        std::copy_n(&prefix_orientations_[i * head * 4], head * 4, &orientations[i * frames * 4]);
        std::copy_n(&resumed.positions_m[i * own * 3], own * 3, &positions[(i * frames + head) * 3]);
        std::copy_n(&resumed.orientations[i * own * 4], own * 4, &orientations[(i * frames + head) * 4]);
    }
    resumed.positions_m = std::move(positions);
    resumed.orientations = std::move(orientations);
    resumed.first_frame = 0;
    resumed.frame_count = static_cast<uint32_t>(frames);
    std::vector<Checkpoint> checkpoints = prefix_checkpoints_;
    const PortableRandom::State own_stream = initial_perturbation_state(base_seed_, resumed.world_index);
    for (Checkpoint& c : checkpoints) c.perturbation_random_state = own_stream;
    checkpoints.insert(checkpoints.end(), std::make_move_iterator(resumed.checkpoints.begin()),
                       std::make_move_iterator(resumed.checkpoints.end()));
    resumed.checkpoints = std::move(checkpoints);
}

}  // namespace mwb
