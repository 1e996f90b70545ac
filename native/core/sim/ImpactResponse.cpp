#include "sim/ImpactResponse.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/PortableMath.h"

namespace mwb {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

ImpactResponse::ImpactResponse(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity,
                               uint64_t perturbation_seed)
    : compiled_(compiled),
      world_(world),
      activity_(activity),
      perturbation_random_(perturbation_seed),
      perturber_(compiled.parameters().alpha_linear, compiled.parameters().lobe_exponent),
      angular_perturber_(compiled.parameters().alpha_angular, compiled.parameters().lobe_exponent) {
    const size_t n = compiled.bodies().size();
    const double g = std::max(norm(compiled.scene().world.gravity), 9.81);
    linear_threshold_ = compiled.parameters().impact_linear_factor * compiled.physics_dt_s() * g;
    angular_threshold_ = compiled.parameters().impact_angular_factor * compiled.physics_dt_s() * kPi;
    // Bullet's damping model, as Blender uses it: v *= (1 - d)^dt every step.
    for (const Body& body : compiled.scene().bodies) {
        linear_damping_factor_.push_back(portable::pow(1.0 - body.linear_damping, compiled.physics_dt_s()));
        angular_damping_factor_.push_back(portable::pow(1.0 - body.angular_damping, compiled.physics_dt_s()));
    }
    previous_linear_.resize(n);
    previous_angular_.resize(n);
    rest_since_s_.assign(n, -1.0);
    quiet_since_s_.assign(n, kNotQuiet);
    // Blender's Deactivation speeds where a body has it on; the run's (far lower) elsewhere.
    const SimulationParameters& p = compiled.parameters();
    for (size_t i = 0; i < n; ++i) {
        const Body::Deactivation& d = compiled.scene().bodies[i].deactivation;
        sleep_linear_speed_.push_back(d.enabled ? std::max(p.sleep_linear_speed, d.linear_speed) : p.sleep_linear_speed);
        sleep_angular_speed_.push_back(d.enabled ? std::max(p.sleep_angular_speed, d.angular_speed) : p.sleep_angular_speed);
        if (d.start_deactivated) quiet_since_s_[i] = kQuietSinceBeforeStart;
    }
    impact_partner_.assign(n, kNoImpact);
}

void ImpactResponse::capture_velocities_before_step() {
    for (size_t i = 0; i < compiled_.bodies().size(); ++i) {
        if (!activity_.simulated(i)) continue;
        previous_linear_[i] = from_ode(dBodyGetLinearVel(world_.bodies()[i]));
        previous_angular_[i] = from_ode(dBodyGetAngularVel(world_.bodies()[i]));
    }
}

void ImpactResponse::respond_to_step(const ContactGenerator& contacts, uint64_t step, double t_after_s) {
    for (size_t i = 0; i < compiled_.bodies().size(); ++i) {
        if (!activity_.simulated(i)) continue;
        if (activity_.animated(i, step)) {  // driven, not simulated: no impacts, no rest
            rest_since_s_[i] = -1;
            quiet_since_s_[i] = kNotQuiet;
            continue;
        }
        respond(i, contacts.deepest_contact(i), t_after_s);
    }
}

void ImpactResponse::respond(size_t i, const DeepestContact& contact, double t_after_s) {
    dBodyID body = world_.bodies()[i];
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
    const int32_t partner = contact.other;
    const bool touched = partner >= 0 && approach_speed(i, contact) > linear_threshold_;
    const bool linear_impact = touched && norm(delta_v) > linear_threshold_;
    const bool angular_impact = touched && norm(delta_w) > angular_threshold_;
    // Rolling and sliding keep velocities changing step after step; that is one collision,
    // not one per step. A new collision starts after a quiet step or with a new partner.
    const bool significant = linear_impact || angular_impact;
    const bool new_collision = significant && impact_partner_[i] != partner;
    impact_partner_[i] = significant ? partner : kNoImpact;
    if (new_collision) {
        collisions_.push_back({t_after_s, static_cast<int32_t>(i), partner,
                               world_.initial_states()[i].mass_kg * norm(delta_v)});
        if (p.perturb) {
            if (linear_impact) v = add(v, perturber_.perturbation(delta_v, perturbation_random_));
            if (angular_impact) w = add(w, angular_perturber_.perturbation(delta_w, perturbation_random_));
            ++impacts_perturbed_;
        }
    }
    const std::string& name = compiled_.scene().bodies[i].name;
    v = scale(v, linear_damping_factor_[i]);
    w = scale(w, angular_damping_factor_[i]);
    dBodySetLinearVel(body, v[0], v[1], v[2]);
    dBodySetAngularVel(body, w[0], w[1], w[2]);
    const Vec3 position = from_ode(dBodyGetPosition(body));
    if (!finite(v) || !finite(w) || !finite(position)) throw WorldRejected("body '" + name + "' became non-finite");
    if (norm(v) > p.max_speed_mps)
        throw WorldRejected("body '" + name + "' exploded (speed above " + std::to_string(p.max_speed_mps) + " m/s)");
    if (norm(position) > p.max_distance_m)
        throw WorldRejected("body '" + name + "' left the world (beyond " + std::to_string(p.max_distance_m) + " m)");
    const bool resting = norm(v) < p.rest_linear_speed && norm(w) < p.rest_angular_speed;
    if (!resting) rest_since_s_[i] = -1;
    else if (rest_since_s_[i] < 0) rest_since_s_[i] = t_after_s;
    const bool quiet = norm(v) < sleep_linear_speed_[i] && norm(w) < sleep_angular_speed_[i];
    if (!quiet) quiet_since_s_[i] = kNotQuiet;
    else if (quiet_since_s_[i] == kNotQuiet) quiet_since_s_[i] = t_after_s;
}

// Velocity at `point` of body i as the step began (a static body is still).
Vec3 ImpactResponse::point_velocity_before_step(int32_t i, const Vec3& point) const {
    dBodyID body = world_.bodies()[i];
    if (!body) return {0, 0, 0};
    const bool stepped = activity_.simulated(i);
    const Vec3 v = stepped ? previous_linear_[i] : from_ode(dBodyGetLinearVel(body));
    const Vec3 w = stepped ? previous_angular_[i] : from_ode(dBodyGetAngularVel(body));
    return add(v, cross(w, sub(point, from_ode(dBodyGetPosition(body)))));
}

// How fast body i and its partner closed in along the contact normal: resting and riding
// contacts close at ~0, collisions at the impact speed.
double ImpactResponse::approach_speed(size_t i, const DeepestContact& contact) const {
    const Vec3 relative = sub(point_velocity_before_step(static_cast<int32_t>(i), contact.point),
                              point_velocity_before_step(contact.other, contact.point));
    return std::fabs(dot(relative, contact.normal));
}

bool ImpactResponse::simulated_bodies_at_rest(double t_s) const {
    const double rest_duration_s = compiled_.parameters().rest_duration_s;
    for (size_t i = 0; i < compiled_.bodies().size(); ++i)
        if (activity_.simulated(i) && (rest_since_s_[i] < 0 || t_s - rest_since_s_[i] < rest_duration_s)) return false;
    return true;
}

void ImpactResponse::restart_body(size_t i) {
    impact_partner_[i] = kNoImpact;
    rest_since_s_[i] = -1;
    quiet_since_s_[i] = kNotQuiet;
}

void ImpactResponse::save(Checkpoint& checkpoint) const {
    checkpoint.perturbation_random_state = perturbation_random_.state();
    checkpoint.body_rest_since_s = rest_since_s_;
    checkpoint.body_quiet_since_s = quiet_since_s_;
    checkpoint.body_impact_partner = impact_partner_;
}

void ImpactResponse::restore(const Checkpoint& checkpoint) {
    perturbation_random_ = PortableRandom(checkpoint.perturbation_random_state);
    std::copy_n(checkpoint.body_rest_since_s.begin(), std::min(checkpoint.body_rest_since_s.size(), rest_since_s_.size()),
                rest_since_s_.begin());
    std::copy_n(checkpoint.body_quiet_since_s.begin(),
                std::min(checkpoint.body_quiet_since_s.size(), quiet_since_s_.size()), quiet_since_s_.begin());
    std::copy_n(checkpoint.body_impact_partner.begin(),
                std::min(checkpoint.body_impact_partner.size(), impact_partner_.size()), impact_partner_.begin());
}

void ImpactResponse::finish(double end_s, WorldResult& result) {
    result.contacts = std::move(collisions_);
    result.impacts_perturbed = impacts_perturbed_;
    const size_t n = compiled_.bodies().size();
    result.rest_time_s.assign(n, 0.0);
    for (size_t i = 0; i < n; ++i)
        if (compiled_.bodies()[i].dynamic) result.rest_time_s[i] = rest_since_s_[i] >= 0 ? rest_since_s_[i] : end_s;
}

}  // namespace mwb
