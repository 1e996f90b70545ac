#include "sim/WorldRecorder.h"

#include <algorithm>
#include <utility>

#include "sim/PoseInterpolation.h"

namespace mwb {

WorldRecorder::WorldRecorder(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity,
                             const ImpactResponse& impacts, const RefinementReplay& replay)
    : compiled_(compiled), world_(world), activity_(activity), impacts_(impacts), replay_(replay) {
    frames_.reserve((compiled.total_steps() / compiled.steps_per_frame() + 1) * compiled.bodies().size());
}

void WorldRecorder::resume_from(const Checkpoint& checkpoint) {
    restored_ = &checkpoint;
    first_frame_ = static_cast<uint32_t>(checkpoint.step_index / compiled_.steps_per_frame());
}

void WorldRecorder::record_frame(uint64_t step) {
    const uint32_t frame = static_cast<uint32_t>(step / compiled_.steps_per_frame());
    for (size_t i = 0; i < compiled_.bodies().size(); ++i) {
        // A replayed body records its parent's frame itself, bit for bit.
        if (replay_.active() && activity_.replayed(i)) {
            frames_.push_back(replay_.parent_frame(i, frame));
            continue;
        }
        Transform pose = world_.object_transform(i);
        if (compiled_.bodies()[i].kinematic)
            pose = sample_animation(compiled_.scene().bodies[i].animation, compiled_.step_time_s(step), pose);
        frames_.push_back(pose);
    }
}

// ODE renormalizes a quaternion when it is set, and that normalization is not idempotent
// (about one orientation in eight flips between two neighbours). So a checkpoint stores each
// orientation as it was *before* being set, and the original run sets it too: a restored run
// sets the same bits and continues from exactly the same state.
void WorldRecorder::save_checkpoint(uint64_t step, uint64_t ode_random_state) {
    if (restored_ && step == restored_->step_index) {
        checkpoints_.push_back(*restored_);
        return;
    }
    Checkpoint c;
    c.step_index = step;
    const size_t n = compiled_.bodies().size();
    c.bodies.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        c.bodies.push_back(world_.body_state(i));
        if (activity_.simulated(i)) world_.set_body_state(i, c.bodies.back());
    }
    for (const JointGroup& group : world_.joint_groups()) c.joint_broken.push_back(group.broken ? 1 : 0);
    c.ode_random_state = ode_random_state;
    impacts_.save(c);
    checkpoints_.push_back(std::move(c));
}

void WorldRecorder::finish(WorldResult& result) {
    const size_t n = compiled_.bodies().size();
    const size_t frames = n ? frames_.size() / n : 0;
    result.first_frame = first_frame_;
    result.frame_count = static_cast<uint32_t>(frames);
    result.positions_m.resize(n * frames * 3);
    result.orientations.resize(n * frames * 4);
    for (size_t f = 0; f < frames; ++f) {
        for (size_t i = 0; i < n; ++i) {
            const Transform& pose = frames_[f * n + i];
            std::copy(pose.location.begin(), pose.location.end(), &result.positions_m[(i * frames + f) * 3]);
            std::copy(pose.rotation.begin(), pose.rotation.end(), &result.orientations[(i * frames + f) * 4]);
        }
    }
    result.checkpoints = std::move(checkpoints_);
}

}  // namespace mwb
