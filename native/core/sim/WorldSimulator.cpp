#include "sim/WorldSimulator.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>

#include "sim/ImpactPerturber.h"
#include "sim/OdeRandom.h"
#include "sim/PortableRandom.h"
#include "sim/OdeWorld.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxContactsPerPair = 4;
constexpr uint64_t kInitialStream = 0;
constexpr uint64_t kPerturbationStream = 1;

// libode has one scratch cache for triangle-mesh collisions in this build; two threads in it at
// once corrupt each other.
std::mutex g_trimesh_mutex;

// Up to `max` contacts between two geoms, holding the mesh lock when either is a triangle mesh.
int collide(dGeomID a, dGeomID b, bool either_is_mesh, int max, dContactGeom* out) {
    if (!either_is_mesh) return dCollide(a, b, max, out, sizeof(dContactGeom));
    std::lock_guard<std::mutex> lock(g_trimesh_mutex);
    return dCollide(a, b, max, out, sizeof(dContactGeom));
}

// Between two poses: linear in position, normalized-linear in rotation (the shorter way round).
Transform interpolate(const Transform& a, const Transform& b, double u) {
    Quat qb = b.rotation;
    if (a.rotation[0] * qb[0] + a.rotation[1] * qb[1] + a.rotation[2] * qb[2] + a.rotation[3] * qb[3] < 0)
        qb = {-qb[0], -qb[1], -qb[2], -qb[3]};
    Quat q;
    for (int k = 0; k < 4; ++k) q[k] = a.rotation[k] + (qb[k] - a.rotation[k]) * u;
    return {add(a.location, scale(sub(b.location, a.location), u)), quat_normalized(q)};
}

Transform sample_animation(const KinematicTrack& track, double time_s, const Transform& fallback) {
    if (track.times_s.empty()) return fallback;
    if (time_s <= track.times_s.front()) return track.transforms.front();
    if (time_s >= track.times_s.back()) return track.transforms.back();
    const size_t hi = static_cast<size_t>(std::upper_bound(track.times_s.begin(), track.times_s.end(), time_s) -
                                          track.times_s.begin());
    const size_t lo = hi - 1;
    const double u = (time_s - track.times_s[lo]) / (track.times_s[hi] - track.times_s[lo]);
    return interpolate(track.transforms[lo], track.transforms[hi], u);
}

// World-frame angular velocity taking rotation q0 to q1 in dt.
Vec3 angular_velocity_between(const Quat& q0, const Quat& q1, double dt) {
    Quat d = quat_multiply(q1, quat_conjugate(q0));
    if (d[0] < 0) d = {-d[0], -d[1], -d[2], -d[3]};
    const Vec3 v{d[1], d[2], d[3]};
    const double s = norm(v);
    if (s < 1e-15) return {0, 0, 0};
    const double angle = 2 * std::atan2(s, d[0]);
    return scale(v, angle / (s * dt));
}

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

intptr_t geom_index(dGeomID geom) { return reinterpret_cast<intptr_t>(dGeomGetData(geom)); }

// A broad-phase pair, keyed by geom indices so it can be put in a fixed order.
struct CandidatePair {
    intptr_t first_index, second_index;
    dGeomID first, second;
    bool operator<(const CandidatePair& other) const {
        return first_index != other.first_index ? first_index < other.first_index : second_index < other.second_index;
    }
};

struct CandidatePairs {
    std::vector<CandidatePair> pairs;
};

void collect_pair(void* data, dGeomID a, dGeomID b) {
    intptr_t ia = geom_index(a), ib = geom_index(b);
    if (ia > ib) {
        std::swap(ia, ib);
        std::swap(a, b);
    }
    static_cast<CandidatePairs*>(data)->pairs.push_back({ia, ib, a, b});
}

// Runs one world step by step. Contacts are generated in a fixed order (sorted geom pairs, not
// the space's internal order, which depends on history) so a restart from a checkpoint replays
// exactly.
class WorldRun {
public:
    /// `lineage`: the refinements this run will make (plan_refinements); the bodies they add or
    /// remove decide which bodies the world has.
    WorldRun(const CompiledScene& compiled, uint64_t base_seed, uint64_t world_index,
             const std::vector<RefineStep>& lineage = {})
        : compiled_(compiled),
          base_seed_(base_seed),
          seed_(derive_world_seed(base_seed, world_index)),
          perturbation_random_(derive_stream_seed(seed_, kPerturbationStream)),
          perturber_(compiled.parameters().alpha_linear, compiled.parameters().lobe_exponent),
          angular_perturber_(compiled.parameters().alpha_angular, compiled.parameters().lobe_exponent) {
        const size_t n = compiled.bodies().size();
        present_.assign(n, 0);
        std::fill(present_.begin(), present_.begin() + static_cast<std::ptrdiff_t>(compiled.sampled_body_count()), 1);
        PortableRandom initial_random(derive_stream_seed(seed_, kInitialStream));
        std::vector<BodyInitialState> initial = draw_initial_states(compiled.scene(), initial_random);
        for (const RefineStep& step : lineage) {
            for (uint32_t body : step.removed) present_[body] = 0;
            if (step.added.empty()) continue;
            // An added body starts as the world that added it drew it, whichever later run replays it.
            PortableRandom added_random(derive_stream_seed(derive_world_seed(base_seed, step.world_index), kInitialStream));
            const std::vector<BodyInitialState> drawn = draw_initial_states(compiled.scene(), added_random);
            for (uint32_t body : step.added) {
                present_[body] = 1;
                initial[body] = drawn[body];
            }
        }
        world_ = std::make_unique<OdeWorld>(compiled, initial, present_);
        result_.present = present_;
        result_.world_index = world_index;
        result_.seed = seed_;
        result_.record_hz = compiled.parameters().record_hz;
        result_.step_hz = compiled.step_hz();
        result_.body_count = static_cast<uint32_t>(compiled.bodies().size());
        rest_since_s_.assign(n, -1.0);
        impact_partner_.assign(n, kNoImpact);
        activator_.assign(n, 0);
        for (size_t i = 0; i < n; ++i) simulated_.push_back(compiled.bodies()[i].dynamic && present_[i] ? 1 : 0);
        // Bullet's damping model, as Blender uses it: v *= (1 - d)^dt every step.
        for (const Body& body : compiled.scene().bodies) {
            linear_damping_factor_.push_back(std::pow(1.0 - body.linear_damping, compiled.physics_dt_s()));
            angular_damping_factor_.push_back(std::pow(1.0 - body.angular_damping, compiled.physics_dt_s()));
        }
        previous_linear_.resize(n);
        previous_angular_.resize(n);
        // The same solver ordering for every world: worlds differ only by their initial states and
        // perturbations, not by solver noise.
        ode_random_state_ = 0;
        const double g = std::max(norm(compiled.scene().world.gravity), 9.81);
        impact_linear_threshold_ = compiled.parameters().impact_linear_factor * compiled.physics_dt_s() * g;
        impact_angular_threshold_ = compiled.parameters().impact_angular_factor * compiled.physics_dt_s() * kPi;
    }

    void restore(const Checkpoint& checkpoint) {
        restored_ = &checkpoint;
        step_ = checkpoint.step_index;
        for (size_t i = 0; i < checkpoint.bodies.size(); ++i) {
            if (!compiled_.bodies()[i].dynamic) continue;
            world_->set_body_state(i, checkpoint.bodies[i]);
            if (compiled_.bodies()[i].handoff_step > 0 && step_ > compiled_.bodies()[i].handoff_step)
                world_->set_kinematic(i, false);
        }
        const auto& groups = world_->joint_groups();
        for (size_t i = 0; i < groups.size() && i < checkpoint.joint_broken.size(); ++i)
            if (checkpoint.joint_broken[i] && !groups[i].joints.empty()) world_->break_joint(i);
        ode_random_state_ = checkpoint.ode_random_state;
        perturbation_random_ = PortableRandom(checkpoint.perturbation_random_state);
        std::copy_n(checkpoint.body_rest_since_s.begin(), std::min(checkpoint.body_rest_since_s.size(), rest_since_s_.size()),
                    rest_since_s_.begin());
        std::copy_n(checkpoint.body_impact_partner.begin(),
                    std::min(checkpoint.body_impact_partner.size(), impact_partner_.size()), impact_partner_.begin());
        first_frame_ = static_cast<uint32_t>(step_ / compiled_.steps_per_frame());
    }

    /// Refinements to apply on the way: at steps[k].branch_step the run switches to simulating
    /// steps[k].bodies while the other bodies replay *replays[k], which must be full-length.
    void plan_refinements(const std::vector<RefineStep>& steps, const std::vector<const WorldResult*>& replays) {
        steps_ = steps;
        replays_ = replays;
        result_.root_world = result_.world_index;
        result_.lineage = steps;
        if (!steps.empty()) {
            result_.world_index = steps.back().world_index;
            result_.seed = derive_world_seed(base_seed_, steps.back().world_index);
        }
    }

    WorldResult run(const std::atomic<bool>* cancel) {
        try {
            loop(cancel);
        } catch (const OdeError& error) {
            reject(error.what());
        }
        finish();
        return std::move(result_);
    }

private:
    double time_at(uint64_t step) const { return static_cast<double>(step) / compiled_.step_hz(); }

    void loop(const std::atomic<bool>* cancel) {
        const uint32_t spf = compiled_.steps_per_frame();
        const size_t max_frames = compiled_.total_steps() / spf + 1 - first_frame_;
        frames_.reserve(max_frames * compiled_.bodies().size());
        bool stop = false;
        for (;; ++step_) {
            if (step_ % compiled_.steps_per_checkpoint() == 0) save_checkpoint();
            if (step_ % spf == 0) {
                record_frame();
                if (cancel && cancel->load(std::memory_order_relaxed)) {
                    result_.status = WorldStatus::Cancelled;
                    return;
                }
            }
            if (stop || step_ >= compiled_.total_steps()) return;
            while (next_refinement_ < steps_.size() && steps_[next_refinement_].branch_step == step_)
                begin_refinement(next_refinement_++);
            step_once();
            if (result_.status == WorldStatus::Rejected) return;
            stop = (step_ + 1) % spf == 0 && compiled_.parameters().stop_at_rest && world_at_rest(time_at(step_ + 1));
        }
    }

    void step_once() {
        const double t = time_at(step_);
        const double dt = compiled_.physics_dt_s();
        drive_kinematic_bodies(t);
        generate_contacts();
        const size_t n = compiled_.bodies().size();
        for (size_t i = 0; i < n; ++i) {
            if (!simulated_[i]) continue;
            previous_linear_[i] = from_ode(dBodyGetLinearVel(world_->bodies()[i]));
            previous_angular_[i] = from_ode(dBodyGetAngularVel(world_->bodies()[i]));
        }
        {
            OdeRandomScope random_scope(ode_random_state_);
            dWorldQuickStep(world_->world(), dt);
        }
        dJointGroupEmpty(world_->contact_group());
        const double t_after = time_at(step_ + 1);
        for (size_t i = 0; i < n; ++i) {
            if (!simulated_[i]) continue;
            if (animated(i)) {  // driven, not simulated: no impacts, no rest
                rest_since_s_[i] = -1;
                continue;
            }
            if (!after_step(i, t_after)) return;
        }
        world_->break_overloaded_joints();
    }

    /// Whether body i follows its keyed animation in the current step (before its handoff).
    bool animated(size_t i) const { return step_ < compiled_.bodies()[i].handoff_step; }

    void drive_kinematic_bodies(double t) {
        if (replay_) drive_replayed_bodies(t);
        const Scene& scene = compiled_.scene();
        const double dt_anim = 1.0 / compiled_.step_hz();
        for (size_t i = 0; i < scene.bodies.size(); ++i) {
            if (!present_[i]) continue;
            // At its handoff a keyed body is let go with the velocity its animation gave it last step.
            if (step_ == compiled_.bodies()[i].handoff_step && step_ > 0 && simulated_[i]) world_->set_kinematic(i, false);
            if (!compiled_.bodies()[i].kinematic && !(animated(i) && simulated_[i])) continue;
            const Transform& rest = world_->initial_states()[i].pose;
            const Transform now = sample_animation(scene.bodies[i].animation, t, rest);
            const Transform next = sample_animation(scene.bodies[i].animation, t + dt_anim, rest);
            // Velocities in physics time so the contact solver sees the animation's true speed.
            const double dt = compiled_.physics_dt_s();
            BodyState s{now.location, now.rotation, scale(sub(next.location, now.location), 1.0 / dt),
                        angular_velocity_between(now.rotation, next.rotation, dt)};
            if (compiled_.bodies()[i].dynamic) {  // a keyed body: ODE holds its centre of mass
                const Vec3& offset = compiled_.bodies()[i].body_frame_offset_m;
                s.position_m = add(now.location, quat_rotate(now.rotation, offset));
                s.linear_velocity = scale(sub(add(next.location, quat_rotate(next.rotation, offset)), s.position_m), 1.0 / dt);
            }
            dBodyID body = world_->bodies()[i];
            dBodySetPosition(body, s.position_m[0], s.position_m[1], s.position_m[2]);
            dQuaternion q{s.orientation[0], s.orientation[1], s.orientation[2], s.orientation[3]};
            dBodySetQuaternion(body, q);
            dBodySetLinearVel(body, s.linear_velocity[0], s.linear_velocity[1], s.linear_velocity[2]);
            dBodySetAngularVel(body, s.angular_velocity[0], s.angular_velocity[1], s.angular_velocity[2]);
        }
    }

    void generate_contacts() {
        candidates_.pairs.clear();
        dSpaceCollide(world_->space(), &candidates_, collect_pair);
        std::sort(candidates_.pairs.begin(), candidates_.pairs.end());
        deepest_contact_.assign(compiled_.bodies().size(), DeepestContact{});
        if (replay_) activate_touched_bodies();
        for (const CandidatePair& pair : candidates_.pairs) collide_pair(pair);
    }

    void collide_pair(const CandidatePair& pair) {
        const auto& owners = world_->geom_owners();
        dGeomID ga = pair.first, gb = pair.second;
        const GeomOwner& oa = owners[pair.first_index];
        const GeomOwner& ob = owners[pair.second_index];
        if (oa.body == ob.body || oa.ghost || ob.ghost) return;
        const bool moving_a = simulated_[oa.body];
        const bool moving_b = simulated_[ob.body];
        if (!moving_a && !moving_b) return;
        if (world_->collision_disabled(oa.body, ob.body)) return;
        dContactGeom contacts[kMaxContactsPerPair];
        const int count = collide(ga, gb, oa.is_mesh || ob.is_mesh, kMaxContactsPerPair, contacts);
        if (count == 0) return;
        const BodyInitialState& ma = world_->initial_states()[oa.body];
        const BodyInitialState& mb = world_->initial_states()[ob.body];
        dSurfaceParameters surface{};
        // Bullet (Blender) combines friction and restitution by multiplication.
        surface.mode = dContactApprox1;
        surface.mu = ma.friction * mb.friction;
        const double bounce = ma.restitution * mb.restitution;
        if (bounce > 0) {
            surface.mode |= dContactBounce;
            surface.bounce = bounce;
            surface.bounce_vel = 0.1;
        }
        dBodyID ba = world_->bodies()[oa.body];
        dBodyID bb = world_->bodies()[ob.body];
        for (int k = 0; k < count; ++k) {
            dContact contact{};
            contact.surface = surface;
            contact.geom = contacts[k];
            dJointID joint = dJointCreateContact(world_->world(), world_->contact_group(), &contact);
            dJointAttach(joint, ba, bb);
            note_contact(oa.body, ob.body, contacts[k]);
            note_contact(ob.body, oa.body, contacts[k]);
        }
    }

    void note_contact(int32_t body, int32_t other, const dContactGeom& contact) {
        DeepestContact& slot = deepest_contact_[body];
        if (contact.depth > slot.depth)
            slot = {other, contact.depth, from_ode(contact.pos), from_ode(contact.normal)};
    }

    // Velocity at `point` of body i as the step began (a static body is still).
    Vec3 point_velocity_before_step(int32_t i, const Vec3& point) const {
        dBodyID body = world_->bodies()[i];
        if (!body) return {0, 0, 0};
        const bool stepped = simulated_[i];
        const Vec3 v = stepped ? previous_linear_[i] : from_ode(dBodyGetLinearVel(body));
        const Vec3 w = stepped ? previous_angular_[i] : from_ode(dBodyGetAngularVel(body));
        return add(v, cross(w, sub(point, from_ode(dBodyGetPosition(body)))));
    }

    // How fast body i and its partner closed in along the contact normal: resting and riding
    // contacts close at ~0, collisions at the impact speed.
    double approach_speed(size_t i) const {
        const DeepestContact& c = deepest_contact_[i];
        const Vec3 relative = sub(point_velocity_before_step(static_cast<int32_t>(i), c.point),
                                  point_velocity_before_step(c.other, c.point));
        return std::fabs(dot(relative, c.normal));
    }

    // Impact detection, perturbation, damping, explosion check and rest tracking for body i.
    bool after_step(size_t i, double t_after) {
        dBodyID body = world_->bodies()[i];
        const SimulationParameters& p = compiled_.parameters();
        const double dt = compiled_.physics_dt_s();
        Vec3 v = from_ode(dBodyGetLinearVel(body));
        Vec3 w = from_ode(dBodyGetAngularVel(body));
        const Vec3 delta_v = sub(sub(v, previous_linear_[i]), scale(compiled_.scene().world.gravity, dt));
        const Vec3 delta_w = sub(w, previous_angular_[i]);
        // Only collisions are impacts: joint and motor forces also change velocities but are not
        // events an observer would judge, and perturbing them would add noise to every chain.
        // Resting and riding contacts jitter under the iterative solver; only bodies that ran into
        // each other faster than the linear threshold collide.
        const int32_t partner = deepest_contact_[i].other;
        const bool touched = partner >= 0 && approach_speed(i) > impact_linear_threshold_;
        const bool linear_impact = touched && norm(delta_v) > impact_linear_threshold_;
        const bool angular_impact = touched && norm(delta_w) > impact_angular_threshold_;
        // Rolling and sliding keep velocities changing step after step; that is one collision,
        // not one per step. A new collision starts after a quiet step or with a new partner.
        const bool significant = linear_impact || angular_impact;
        const bool new_collision = significant && impact_partner_[i] != partner;
        impact_partner_[i] = significant ? partner : kNoImpact;
        if (new_collision) {
            result_.contacts.push_back({t_after, static_cast<int32_t>(i), partner,
                                        world_->initial_states()[i].mass_kg * norm(delta_v)});
            if (p.perturb) {
                if (linear_impact) v = add(v, perturber_.perturbation(delta_v, perturbation_random_));
                if (angular_impact) w = add(w, angular_perturber_.perturbation(delta_w, perturbation_random_));
                ++result_.impacts_perturbed;
            }
        }
        const Body& scene_body = compiled_.scene().bodies[i];
        v = scale(v, linear_damping_factor_[i]);
        w = scale(w, angular_damping_factor_[i]);
        dBodySetLinearVel(body, v[0], v[1], v[2]);
        dBodySetAngularVel(body, w[0], w[1], w[2]);
        const Vec3 position = from_ode(dBodyGetPosition(body));
        if (!finite(v) || !finite(w) || !finite(position)) return reject("body '" + scene_body.name + "' became non-finite");
        if (norm(v) > p.max_speed_mps)
            return reject("body '" + scene_body.name + "' exploded (speed above " + std::to_string(p.max_speed_mps) + " m/s)");
        if (norm(position) > p.max_distance_m)
            return reject("body '" + scene_body.name + "' left the world (beyond " + std::to_string(p.max_distance_m) + " m)");
        const bool resting = norm(v) < p.rest_linear_speed && norm(w) < p.rest_angular_speed;
        if (!resting) rest_since_s_[i] = -1;
        else if (rest_since_s_[i] < 0) rest_since_s_[i] = t_after;
        return true;
    }

    static Vec3 from_ode(const dReal* v) { return {v[0], v[1], v[2]}; }

    bool reject(const std::string& reason) {
        result_.status = WorldStatus::Rejected;
        result_.reject_reason = reason;
        return false;
    }

    bool world_at_rest(double t) const {
        const Scene& scene = compiled_.scene();
        for (size_t i = 0; i < scene.bodies.size(); ++i) {
            const CompiledBody& body = compiled_.bodies()[i];
            if (body.kinematic && present_[i] && !scene.bodies[i].animation.times_s.empty() && t < scene.bodies[i].animation.times_s.back())
                return false;
            if (simulated_[i] && (rest_since_s_[i] < 0 || t - rest_since_s_[i] < compiled_.parameters().rest_duration_s))
                return false;
        }
        // Replayed bodies are only defined while their world lasts.
        return !replay_ || t >= replay_->simulated_time_s;
    }

    // --- refinement ---------------------------------------------------------------------

    // Switches to refinement k: its bodies (and bodies jointed to them) are simulated, every other
    // dynamic body replays the world being refined, and ghosts of the chosen bodies follow their
    // old paths to find bodies they used to touch. Added bodies are simulated (or, if passive,
    // wake what they touch); removed bodies leave a ghost, and their joint partners are freed.
    void begin_refinement(size_t k) {
        const RefineStep& step = steps_[k];
        replay_ = replays_[k];
        branch_time_s_ = time_at(step_);
        const size_t n = compiled_.bodies().size();
        std::fill(simulated_.begin(), simulated_.end(), 0);
        std::fill(activator_.begin(), activator_.end(), 0);
        activated_at_s_.assign(n, std::numeric_limits<double>::infinity());
        result_.changed.assign(n, 0);
        for (uint32_t body : step.bodies) activate(body);
        for (uint32_t body : step.added) {
            activate(body);
            if (!compiled_.bodies()[body].dynamic) activator_[body] = 1;
        }
        for (uint32_t body : step.removed) activate_joint_partners(body, false);
        for (size_t i = 0; i < n; ++i)
            if (compiled_.bodies()[i].dynamic && !simulated_[i]) world_->set_kinematic(i, true);
        for (uint32_t body : ghosts_) world_->set_ghost_enabled(body, false);
        ghosts_.clear();
        std::vector<uint32_t> ghosted;
        for (uint32_t body : step.bodies)
            if (compiled_.bodies()[body].dynamic) ghosted.push_back(body);
        ghosted.insert(ghosted.end(), step.removed.begin(), step.removed.end());
        for (uint32_t body : ghosted) {
            world_->add_ghost(body);
            world_->set_ghost_enabled(body, true);
            ghosts_.push_back(body);
        }
        perturbation_random_ = PortableRandom(derive_stream_seed(derive_world_seed(base_seed_, steps_[k].world_index),
                                                                 kPerturbationStream));
        drive_replayed_bodies(branch_time_s_);
    }

    // Starts simulating body i (and, through joints, its partners) from its replayed state.
    void activate(uint32_t i) {
        if (i >= simulated_.size() || simulated_[i] || !compiled_.bodies()[i].dynamic || !present_[i]) return;
        simulated_[i] = 1;
        result_.changed[i] = 1;
        activated_at_s_[i] = time_at(step_);
        if (!animated(i)) world_->set_kinematic(i, false);
        impact_partner_[i] = kNoImpact;
        rest_since_s_[i] = -1;
        activate_joint_partners(i, true);
    }

    // Activates the bodies jointed to body i: through the joints this world has (`live_only`), or
    // through every enabled constraint of the scene (a removed body's partners lose their joint,
    // so they move anew).
    void activate_joint_partners(uint32_t i, bool live_only) {
        const Scene& scene = compiled_.scene();
        const auto& groups = world_->joint_groups();
        for (size_t c = 0; c < scene.constraints.size(); ++c) {
            const bool joined = live_only ? !groups[c].joints.empty() && !groups[c].broken : scene.constraints[c].enabled;
            if (!joined) continue;
            const int a = scene.body_index(scene.constraints[c].body_a);
            const int b = scene.body_index(scene.constraints[c].body_b);
            if (a == static_cast<int>(i) && b >= 0) activate(static_cast<uint32_t>(b));
            if (b == static_cast<int>(i) && a >= 0) activate(static_cast<uint32_t>(a));
        }
    }

    // A replayed body starts being simulated when a simulated body or a ghost touches it; repeated
    // until nothing more changes, so the result does not depend on the order of the pairs.
    void activate_touched_bodies() {
        const auto& owners = world_->geom_owners();
        for (bool changed = true; changed;) {
            changed = false;
            for (const CandidatePair& pair : candidates_.pairs) {
                const GeomOwner& oa = owners[pair.first_index];
                const GeomOwner& ob = owners[pair.second_index];
                if (oa.body == ob.body || (oa.ghost && ob.ghost)) continue;
                const bool active_a = oa.ghost || simulated_[oa.body] || activator_[oa.body];
                const bool active_b = ob.ghost || simulated_[ob.body] || activator_[ob.body];
                const bool replayed_a = !oa.ghost && replayed(oa.body);
                const bool replayed_b = !ob.ghost && replayed(ob.body);
                if (!((active_a && replayed_b) || (active_b && replayed_a))) continue;
                if (world_->collision_disabled(oa.body, ob.body)) continue;
                dContactGeom contact;
                if (collide(pair.first, pair.second, oa.is_mesh || ob.is_mesh, 1, &contact) == 0) continue;
                activate(static_cast<uint32_t>(replayed_a ? oa.body : ob.body));
                changed = true;
            }
        }
    }

    bool replayed(int32_t body) const {
        return compiled_.bodies()[body].dynamic && present_[body] && !simulated_[body];
    }

    // Pose of body i in the world being refined, at frame f (its last frame after its end).
    Transform replay_frame(size_t i, uint32_t f) const {
        const size_t frames = replay_->frame_count;
        const size_t k = std::min<size_t>(f, frames - 1);
        const double* p = &replay_->positions_m[(i * frames + k) * 3];
        const double* q = &replay_->orientations[(i * frames + k) * 4];
        return {{p[0], p[1], p[2]}, {q[0], q[1], q[2], q[3]}};
    }

    // The replayed pose between recorded frames, linear in position, normalized-linear in rotation.
    Transform replay_pose(size_t i, double t) const {
        const double frame = t * compiled_.parameters().record_hz;
        const auto f = static_cast<uint32_t>(std::floor(frame));
        const double u = frame - f;
        const Transform a = replay_frame(i, f);
        return u <= 0 ? a : interpolate(a, replay_frame(i, f + 1), u);
    }

    // Centre-of-mass state of body i on the replayed path at t, moving towards where it is one step later.
    BodyState replay_state(size_t i, double t) const {
        const double dt_anim = 1.0 / compiled_.step_hz();
        const Vec3& offset = compiled_.bodies()[i].body_frame_offset_m;
        const Transform now = replay_pose(i, t), next = replay_pose(i, t + dt_anim);
        const Vec3 com_now = add(now.location, quat_rotate(now.rotation, offset));
        const Vec3 com_next = add(next.location, quat_rotate(next.rotation, offset));
        const double dt = compiled_.physics_dt_s();
        const Vec3 v = scale(sub(com_next, com_now), 1.0 / dt);
        const Vec3 w = angular_velocity_between(now.rotation, next.rotation, dt);
        return {com_now, now.rotation, v, w};
    }

    void drive_replayed_bodies(double t) {
        for (size_t i = 0; i < compiled_.bodies().size(); ++i)
            if (replayed(static_cast<int32_t>(i))) world_->set_body_state(i, replay_state(i, t));
        for (uint32_t body : ghosts_) world_->set_ghost_state(body, replay_state(body, t));
    }

    // A refined world before its branch is its parent's; so are the events of bodies it did not
    // touch, and of the others until they were touched.
    void splice_parent() {
        const size_t n = compiled_.bodies().size();
        const size_t own = result_.frame_count;
        const size_t head = first_frame_;
        const size_t frames = head + own;
        std::vector<double> positions(n * frames * 3), orientations(n * frames * 4);
        for (size_t i = 0; i < n; ++i) {
            for (size_t f = 0; f < head; ++f) {
                const Transform pose = replay_frame(i, static_cast<uint32_t>(f));
                std::copy(pose.location.begin(), pose.location.end(), &positions[(i * frames + f) * 3]);
                std::copy(pose.rotation.begin(), pose.rotation.end(), &orientations[(i * frames + f) * 4]);
            }
            std::copy(&result_.positions_m[i * own * 3], &result_.positions_m[(i + 1) * own * 3],
                      &positions[(i * frames + head) * 3]);
            std::copy(&result_.orientations[i * own * 4], &result_.orientations[(i + 1) * own * 4],
                      &orientations[(i * frames + head) * 4]);
        }
        result_.positions_m = std::move(positions);
        result_.orientations = std::move(orientations);
        result_.first_frame = 0;
        result_.frame_count = static_cast<uint32_t>(frames);
        std::vector<ContactEvent> events;
        for (const ContactEvent& e : replay_->contacts) {
            if (e.body >= 0 && !present_[static_cast<size_t>(e.body)]) continue;
            if (e.time_s <= branch_time_s_ || (e.body >= 0 && e.time_s <= activated_at_s_[static_cast<size_t>(e.body)]))
                events.push_back(e);
        }
        for (const ContactEvent& e : result_.contacts)
            if (e.time_s > branch_time_s_ && e.body >= 0 && e.time_s > activated_at_s_[static_cast<size_t>(e.body)])
                events.push_back(e);
        std::stable_sort(events.begin(), events.end(), [](const ContactEvent& a, const ContactEvent& b) { return a.time_s < b.time_s; });
        result_.contacts = std::move(events);
        for (size_t i = 0; i < n; ++i)
            if (!result_.changed[i]) result_.rest_time_s[i] = replay_->rest_time_s[i];
    }

    // ODE renormalizes a quaternion when it is set, and that normalization is not idempotent
    // (about one orientation in eight flips between two neighbours). So a checkpoint stores each
    // orientation as it was *before* being set, and the original run sets it too: a restored run
    // sets the same bits and continues from exactly the same state.
    void save_checkpoint() {
        if (restored_ && step_ == restored_->step_index) {
            result_.checkpoints.push_back(*restored_);
            return;
        }
        Checkpoint c;
        c.step_index = step_;
        const size_t n = compiled_.bodies().size();
        c.bodies.reserve(n);
        for (size_t i = 0; i < n; ++i) {
            c.bodies.push_back(world_->body_state(i));
            if (simulated_[i]) world_->set_body_state(i, c.bodies.back());
        }
        for (const JointGroup& group : world_->joint_groups()) c.joint_broken.push_back(group.broken ? 1 : 0);
        c.ode_random_state = ode_random_state_;
        c.perturbation_random_state = perturbation_random_.state();
        c.body_rest_since_s = rest_since_s_;
        c.body_impact_partner = impact_partner_;
        result_.checkpoints.push_back(std::move(c));
    }

    void record_frame() {
        const uint32_t frame = static_cast<uint32_t>(step_ / compiled_.steps_per_frame());
        for (size_t i = 0; i < compiled_.bodies().size(); ++i) {
            // A replayed body records its parent's frame itself, bit for bit.
            if (replay_ && replayed(static_cast<int32_t>(i))) {
                frames_.push_back(replay_frame(i, frame));
                continue;
            }
            Transform pose = world_->object_transform(i);
            if (compiled_.bodies()[i].kinematic)
                pose = sample_animation(compiled_.scene().bodies[i].animation, time_at(step_), pose);
            frames_.push_back(pose);
        }
    }

    void finish() {
        const size_t n = compiled_.bodies().size();
        const size_t frames = n ? frames_.size() / n : 0;
        result_.first_frame = first_frame_;
        result_.frame_count = static_cast<uint32_t>(frames);
        result_.positions_m.resize(n * frames * 3);
        result_.orientations.resize(n * frames * 4);
        for (size_t f = 0; f < frames; ++f) {
            for (size_t i = 0; i < n; ++i) {
                const Transform& pose = frames_[f * n + i];
                std::copy(pose.location.begin(), pose.location.end(), &result_.positions_m[(i * frames + f) * 3]);
                std::copy(pose.rotation.begin(), pose.rotation.end(), &result_.orientations[(i * frames + f) * 4]);
            }
        }
        result_.simulated_time_s = time_at(step_);
        result_.rest_time_s.assign(n, 0.0);
        for (size_t i = 0; i < n; ++i)
            if (compiled_.bodies()[i].dynamic)
                result_.rest_time_s[i] = rest_since_s_[i] >= 0 ? rest_since_s_[i] : result_.simulated_time_s;
        if (replay_) splice_parent();
    }

    const CompiledScene& compiled_;
    uint64_t base_seed_;
    uint64_t seed_;
    PortableRandom perturbation_random_;
    ImpactPerturber perturber_;
    ImpactPerturber angular_perturber_;
    std::unique_ptr<OdeWorld> world_;
    WorldResult result_;
    uint64_t step_ = 0;
    uint32_t first_frame_ = 0;
    const Checkpoint* restored_ = nullptr;
    std::vector<uint8_t> simulated_;     ///< per body: stepped by ODE now (not fixed, animated or replayed)
    std::vector<uint8_t> present_;       ///< per body: exists in this world
    std::vector<uint8_t> activator_;     ///< per body: a passive body added now, waking what it touches
    std::vector<RefineStep> steps_;
    std::vector<const WorldResult*> replays_;
    size_t next_refinement_ = 0;
    const WorldResult* replay_ = nullptr;  ///< the world being refined, once the last switch happened
    std::vector<uint32_t> ghosts_;         ///< bodies whose ghost follows the replay
    std::vector<double> activated_at_s_;   ///< per body: when it started being simulated anew
    double branch_time_s_ = 0;
    uint64_t ode_random_state_ = 0;
    double impact_linear_threshold_ = 0;
    double impact_angular_threshold_ = 0;
    std::vector<double> rest_since_s_;
    std::vector<int32_t> impact_partner_;
    std::vector<double> linear_damping_factor_, angular_damping_factor_;
    std::vector<Vec3> previous_linear_, previous_angular_;
    struct DeepestContact {
        int32_t other = -1;
        double depth = -1;
        Vec3 point{0, 0, 0}, normal{0, 0, 1};
    };
    std::vector<DeepestContact> deepest_contact_;
    std::vector<Transform> frames_;
    CandidatePairs candidates_;
};

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
    std::vector<const WorldResult*> replays;
    for (size_t k = steps.size(); k-- > 0;) {
        if (!effective.empty() && steps[k].branch_step >= effective.front().branch_step) continue;
        effective.insert(effective.begin(), steps[k]);
        replays.insert(replays.begin(), &chain[k]);
    }
    const WorldResult& root = chain.front();
    WorldRun run(compiled, base_seed, root.world_index, steps);
    const Checkpoint* start = nullptr;
    for (const Checkpoint& c : root.checkpoints)
        if (c.step_index <= effective.front().branch_step) start = &c;
    // From t = 0 (always so when the lineage adds or removes bodies) the run starts afresh: a
    // sampled checkpoint would overwrite the starting state of added bodies.
    if (start && start->step_index > 0) run.restore(*start);
    run.plan_refinements(effective, replays);
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
