#include "sim/WorldRun.h"

#include <algorithm>
#include <cstddef>
#include <utility>

#include "sim/OdeMessages.h"
#include "sim/OdeRandom.h"
#include "sim/PortableRandom.h"

namespace mwb {

WorldRun::Bodies WorldRun::draw_bodies(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                                       const std::vector<RefineStep>& lineage) {
    Bodies bodies;
    bodies.present.assign(compiled.bodies().size(), 0);
    std::fill(bodies.present.begin(),
              bodies.present.begin() + static_cast<std::ptrdiff_t>(compiled.sampled_body_count()), 1);
    PortableRandom initial_random(derive_stream_seed(derive_world_seed(base_seed, world_index), kInitialStateStream));
    bodies.initial = draw_initial_states(compiled.scene(), initial_random);
    for (const RefineStep& step : lineage) {
        for (uint32_t body : step.removed) bodies.present[body] = 0;
        if (step.added.empty()) continue;
        // An added body starts as the world that added it drew it, whichever later run replays it.
        PortableRandom added_random(derive_stream_seed(derive_world_seed(base_seed, step.world_index), kInitialStateStream));
        const std::vector<BodyInitialState> drawn = draw_initial_states(compiled.scene(), added_random);
        for (uint32_t body : step.added) {
            bodies.present[body] = 1;
            bodies.initial[body] = drawn[body];
        }
    }
    return bodies;
}

WorldRun::WorldRun(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
                   const std::vector<RefineStep>& lineage)
    : WorldRun(compiled, base_seed, world_index, draw_bodies(compiled, base_seed, world_index, lineage)) {}

WorldRun::WorldRun(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index, const Bodies& bodies)
    : compiled_(compiled),
      base_seed_(base_seed),
      world_(compiled, bodies.initial, bodies.present),
      activity_(compiled, bodies.present),
      contacts_(world_, activity_),
      impacts_(compiled, world_, activity_,
               derive_stream_seed(derive_world_seed(base_seed, world_index), kPerturbationStream)),
      sleep_(compiled, world_, activity_, impacts_),
      kinematics_(compiled, world_, activity_),
      replay_(compiled, base_seed, world_, activity_, impacts_),
      recorder_(compiled, world_, activity_, impacts_, replay_) {
    result_.present = bodies.present;
    result_.world_index = world_index;
    result_.seed = derive_world_seed(base_seed, world_index);
    result_.record_hz = compiled.parameters().record_hz;
    result_.step_hz = compiled.step_hz();
    result_.body_count = static_cast<uint32_t>(compiled.bodies().size());
    contacts_.set_sleep(&sleep_);
    sleep_.restore(0, 0.0);
}

void WorldRun::restore(const Checkpoint& checkpoint) {
    step_ = checkpoint.step_index;
    for (size_t i = 0; i < checkpoint.bodies.size(); ++i)
        if (compiled_.bodies()[i].dynamic) world_.set_body_state(i, checkpoint.bodies[i]);
    kinematics_.resume_at(step_);
    const auto& groups = world_.joint_groups();
    for (size_t i = 0; i < groups.size() && i < checkpoint.joint_broken.size(); ++i)
        if (checkpoint.joint_broken[i] && !groups[i].joints.empty()) world_.break_joint(i);
    ode_random_state_ = checkpoint.ode_random_state;
    impacts_.restore(checkpoint);
    sleep_.restore(step_, compiled_.step_time_s(step_));
    recorder_.resume_from(checkpoint);
}

void WorldRun::plan_refinements(const std::vector<RefineStep>& steps, const std::vector<const WorldResult*>& parents) {
    replay_.plan(steps, parents);
    result_.root_world = result_.world_index;
    result_.lineage = steps;
    if (!steps.empty()) {
        result_.world_index = steps.back().world_index;
        result_.seed = derive_world_seed(base_seed_, steps.back().world_index);
    }
}

WorldResult WorldRun::run(const std::atomic<bool>* cancel) {
    try {
        loop(cancel);
    } catch (const OdeError& error) {
        reject(error.what());
    } catch (const WorldRejected& rejection) {
        reject(rejection.what());
    }
    finish();
    return std::move(result_);
}

void WorldRun::loop(const std::atomic<bool>* cancel) {
    const uint32_t spf = compiled_.steps_per_frame();
    bool stop = false;
    for (;; ++step_) {
        if (step_ % compiled_.steps_per_checkpoint() == 0) recorder_.save_checkpoint(step_, ode_random_state_);
        if (step_ % spf == 0) {
            recorder_.record_frame(step_);
            if (cancel && cancel->load(std::memory_order_relaxed)) {
                result_.status = WorldStatus::Cancelled;
                return;
            }
        }
        if (stop || step_ >= compiled_.total_steps()) return;
        replay_.begin_due(step_);
        step_once();
        stop = (step_ + 1) % spf == 0 && compiled_.parameters().stop_at_rest && at_rest(compiled_.step_time_s(step_ + 1));
    }
}

void WorldRun::step_once() {
    const double t = compiled_.step_time_s(step_);
    if (replay_.active()) replay_.drive_replayed_bodies(t);
    kinematics_.drive(step_, t);
    contacts_.find_candidate_pairs();
    if (replay_.active()) replay_.activate_touched_bodies(contacts_, step_);
    sleep_.wake_touched(contacts_, step_);
    contacts_.create_contacts();
    impacts_.capture_velocities_before_step();
    {
        OdeRandomScope random_scope(ode_random_state_);
        OdeMessageCapture messages(result_.ode_messages, t);
        dWorldQuickStep(world_.world(), compiled_.physics_dt_s());
    }
    dJointGroupEmpty(world_.contact_group());
    impacts_.respond_to_step(contacts_, step_, compiled_.step_time_s(step_ + 1));
    world_.break_overloaded_joints();
    sleep_.settle(step_, compiled_.step_time_s(step_ + 1));
}

bool WorldRun::at_rest(double t_s) const {
    // Replayed bodies are only defined while their world lasts.
    return !kinematics_.animation_playing(t_s) && impacts_.simulated_bodies_at_rest(t_s) &&
           (!replay_.active() || t_s >= replay_.parent_end_s());
}

void WorldRun::reject(const char* reason) {
    result_.status = WorldStatus::Rejected;
    result_.reject_reason = reason;
}

void WorldRun::finish() {
    recorder_.finish(result_);
    result_.simulated_time_s = compiled_.step_time_s(step_);
    impacts_.finish(result_.simulated_time_s, result_);
    if (replay_.active()) replay_.finish(result_);
}

}  // namespace mwb
