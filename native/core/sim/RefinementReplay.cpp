#include "sim/RefinementReplay.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "sim/PoseInterpolation.h"
#include "sim/PortableRandom.h"

namespace mwb {

RefinementReplay::RefinementReplay(const CompiledScene& compiled, uint64_t base_seed, OdeWorld& world,
                                   BodyActivity& activity, ImpactResponse& impacts)
    : compiled_(compiled),
      base_seed_(base_seed),
      world_(world),
      activity_(activity),
      impacts_(impacts),
      activator_(compiled.bodies().size(), 0) {}

void RefinementReplay::plan(const std::vector<RefineStep>& steps, const std::vector<const WorldResult*>& parents) {
    steps_ = steps;
    parents_ = parents;
}

void RefinementReplay::begin_due(uint64_t step) {
    while (next_ < steps_.size() && steps_[next_].branch_step == step) begin(next_++, step);
}

// Switches to refinement k: its bodies (and bodies jointed to them) are simulated, every other
// dynamic body replays the world being refined, and ghosts of the chosen bodies follow their
// old paths to find bodies they used to touch. Added bodies are simulated (or, if passive,
// wake what they touch); removed bodies leave a ghost, and their joint partners are freed.
void RefinementReplay::begin(size_t k, uint64_t step) {
    const RefineStep& refinement = steps_[k];
    parent_ = parents_[k];
    branch_time_s_ = compiled_.step_time_s(step);
    const size_t n = compiled_.bodies().size();
    activity_.stop_simulating();
    std::fill(activator_.begin(), activator_.end(), 0);
    activated_at_s_.assign(n, std::numeric_limits<double>::infinity());
    changed_.assign(n, 0);
    for (uint32_t body : refinement.bodies) activate(body, step);
    for (uint32_t body : refinement.added) {
        activate(body, step);
        if (!compiled_.bodies()[body].dynamic) activator_[body] = 1;
    }
    for (uint32_t body : refinement.removed) activate_joint_partners(body, false, step);
    for (size_t i = 0; i < n; ++i)
        if (compiled_.bodies()[i].dynamic && !activity_.simulated(i)) world_.set_kinematic(i, true);
    for (uint32_t body : ghosts_) world_.set_ghost_enabled(body, false);
    ghosts_.clear();
    std::vector<uint32_t> ghosted;
    for (uint32_t body : refinement.bodies)
        if (compiled_.bodies()[body].dynamic) ghosted.push_back(body);
    ghosted.insert(ghosted.end(), refinement.removed.begin(), refinement.removed.end());
    for (uint32_t body : ghosted) {
        world_.add_ghost(body);
        world_.set_ghost_enabled(body, true);
        ghosts_.push_back(body);
    }
    impacts_.reseed_perturbations(
        derive_stream_seed(derive_world_seed(base_seed_, refinement.world_index), kPerturbationStream));
    drive_replayed_bodies(branch_time_s_);
}

// Starts simulating body i (and, through joints, its partners) from its replayed state.
void RefinementReplay::activate(uint32_t i, uint64_t step) {
    if (i >= compiled_.bodies().size() || activity_.simulated(i) || !compiled_.bodies()[i].dynamic || !activity_.present(i))
        return;
    activity_.set_simulated(i);
    changed_[i] = 1;
    activated_at_s_[i] = compiled_.step_time_s(step);
    if (!activity_.animated(i, step)) world_.set_kinematic(i, false);
    impacts_.restart_body(i);
    activate_joint_partners(i, true, step);
}

// Activates the bodies jointed to body i: through the joints this world has (`live_only`), or
// through every enabled constraint of the scene (a removed body's partners lose their joint,
// so they move anew).
void RefinementReplay::activate_joint_partners(uint32_t i, bool live_only, uint64_t step) {
    const Scene& scene = compiled_.scene();
    const auto& groups = world_.joint_groups();
    for (size_t c = 0; c < scene.constraints.size(); ++c) {
        const bool joined = live_only ? !groups[c].joints.empty() && !groups[c].broken : scene.constraints[c].enabled;
        if (!joined) continue;
        const int a = scene.body_index(scene.constraints[c].body_a);
        const int b = scene.body_index(scene.constraints[c].body_b);
        if (a == static_cast<int>(i) && b >= 0) activate(static_cast<uint32_t>(b), step);
        if (b == static_cast<int>(i) && a >= 0) activate(static_cast<uint32_t>(a), step);
    }
}

// Repeated until nothing more changes, so the result does not depend on the order of the pairs.
void RefinementReplay::activate_touched_bodies(const ContactGenerator& contacts, uint64_t step) {
    const auto& owners = world_.geom_owners();
    for (bool woke_any = true; woke_any;) {
        woke_any = false;
        for (const CandidatePair& pair : contacts.candidate_pairs()) {
            const GeomOwner& oa = owners[pair.first_index];
            const GeomOwner& ob = owners[pair.second_index];
            if (oa.body == ob.body || (oa.ghost && ob.ghost)) continue;
            const bool active_a = oa.ghost || activity_.simulated(oa.body) || activator_[oa.body];
            const bool active_b = ob.ghost || activity_.simulated(ob.body) || activator_[ob.body];
            const bool replayed_a = !oa.ghost && activity_.replayed(oa.body);
            const bool replayed_b = !ob.ghost && activity_.replayed(ob.body);
            if (!((active_a && replayed_b) || (active_b && replayed_a))) continue;
            if (world_.collision_disabled(oa.body, ob.body)) continue;
            if (!contacts.touching(pair)) continue;
            activate(static_cast<uint32_t>(replayed_a ? oa.body : ob.body), step);
            woke_any = true;
        }
    }
}

Transform RefinementReplay::parent_frame(size_t i, uint32_t f) const {
    const size_t frames = parent_->frame_count;
    const size_t k = std::min<size_t>(f, frames - 1);
    const double* p = &parent_->positions_m[(i * frames + k) * 3];
    const double* q = &parent_->orientations[(i * frames + k) * 4];
    return {{p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]}};
}

// The replayed pose between recorded frames.
Transform RefinementReplay::parent_pose(size_t i, double t_s) const {
    const double frame = t_s * compiled_.parameters().record_hz;
    const auto f = static_cast<uint32_t>(std::floor(frame));
    const double u = frame - f;
    const Transform a = parent_frame(i, f);
    return u <= 0 ? a : interpolate_pose(a, parent_frame(i, f + 1), u);
}

// Body i on the replayed path at t, moving towards where it is one step later.
BodyState RefinementReplay::parent_state(size_t i, double t_s) const {
    const double dt_anim = 1.0 / compiled_.step_hz();
    return state_moving_between(parent_pose(i, t_s), parent_pose(i, t_s + dt_anim),
                                compiled_.bodies()[i].body_frame_offset_m, compiled_.physics_dt_s());
}

void RefinementReplay::drive_replayed_bodies(double t_s) {
    for (size_t i = 0; i < compiled_.bodies().size(); ++i)
        if (activity_.replayed(i)) world_.set_body_state(i, parent_state(i, t_s));
    for (uint32_t body : ghosts_) world_.set_ghost_state(body, parent_state(body, t_s));
}

void RefinementReplay::finish(WorldResult& result) const {
    result.changed = changed_;
    splice_parent_frames(result);
    splice_parent_events(result);
    for (size_t i = 0; i < compiled_.bodies().size(); ++i)
        if (!result.changed[i]) result.rest_time_s[i] = parent_->rest_time_s[i];
}

// A refined world before its branch is its parent's.
void RefinementReplay::splice_parent_frames(WorldResult& result) const {
    const size_t n = compiled_.bodies().size();
    const size_t own = result.frame_count;
    const size_t head = result.first_frame;
    const size_t frames = head + own;
    std::vector<double> positions(n * frames * 3), orientations(n * frames * 4);
    for (size_t i = 0; i < n; ++i) {
        for (size_t f = 0; f < head; ++f) {
            const Transform pose = parent_frame(i, static_cast<uint32_t>(f));
            std::copy(pose.location.begin(), pose.location.end(), &positions[(i * frames + f) * 3]);
            std::copy(pose.rotation.begin(), pose.rotation.end(), &orientations[(i * frames + f) * 4]);
        }
        std::copy(&result.positions_m[i * own * 3], &result.positions_m[(i + 1) * own * 3],
                  &positions[(i * frames + head) * 3]);
        std::copy(&result.orientations[i * own * 4], &result.orientations[(i + 1) * own * 4],
                  &orientations[(i * frames + head) * 4]);
    }
    result.positions_m = std::move(positions);
    result.orientations = std::move(orientations);
    result.first_frame = 0;
    result.frame_count = static_cast<uint32_t>(frames);
}

// So are the events of bodies it did not touch, and of the others until they were touched.
void RefinementReplay::splice_parent_events(WorldResult& result) const {
    std::vector<ContactEvent> events;
    for (const ContactEvent& e : parent_->contacts) {
        if (e.body >= 0 && !activity_.present(static_cast<size_t>(e.body))) continue;
        if (e.time_s <= branch_time_s_ || (e.body >= 0 && e.time_s <= activated_at_s_[static_cast<size_t>(e.body)]))
            events.push_back(e);
    }
    for (const ContactEvent& e : result.contacts)
        if (e.time_s > branch_time_s_ && e.body >= 0 && e.time_s > activated_at_s_[static_cast<size_t>(e.body)])
            events.push_back(e);
    std::stable_sort(events.begin(), events.end(), [](const ContactEvent& a, const ContactEvent& b) { return a.time_s < b.time_s; });
    result.contacts = std::move(events);
}

}  // namespace mwb
