#include "sim/KinematicDriver.h"

#include "sim/PoseInterpolation.h"

namespace mwb {

KinematicDriver::KinematicDriver(const CompiledScene& compiled, OdeWorld& world, const BodyActivity& activity)
    : compiled_(compiled), world_(world), activity_(activity) {}

void KinematicDriver::drive(uint64_t step, double t_s) {
    const Scene& scene = compiled_.scene();
    const double dt_anim = 1.0 / compiled_.step_hz();
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
        if (!activity_.present(i)) continue;
        const CompiledBody& body = compiled_.bodies()[i];
        // At its handoff a keyed body is let go with the velocity its animation gave it last step.
        if (step == body.handoff_step && step > 0 && activity_.simulated(i)) world_.set_kinematic(i, false);
        if (!body.kinematic && !(activity_.animated(i, step) && activity_.simulated(i))) continue;
        const Transform& rest = world_.initial_states()[i].pose;
        const Transform now = sample_animation(scene.bodies[i].animation, t_s, rest);
        const Transform next = sample_animation(scene.bodies[i].animation, t_s + dt_anim, rest);
        // Velocities in physics time so the contact solver sees the animation's true speed.
        const double dt = compiled_.physics_dt_s();
        if (body.dynamic) {  // a keyed body: ODE holds its centre of mass
            world_.set_body_state(i, state_moving_between(now, next, body.body_frame_offset_m, dt));
        } else {  // an "Animated" body: ODE holds its object origin
            world_.set_body_state(i, {now.location, now.rotation, scale(sub(next.location, now.location), 1.0 / dt),
                                      angular_velocity_between(now.rotation, next.rotation, dt)});
        }
    }
}

void KinematicDriver::resume_at(uint64_t step) {
    for (size_t i = 0; i < compiled_.bodies().size(); ++i) {
        const CompiledBody& body = compiled_.bodies()[i];
        if (body.dynamic && body.handoff_step > 0 && step > body.handoff_step) world_.set_kinematic(i, false);
    }
}

bool KinematicDriver::animation_playing(double t_s) const {
    const Scene& scene = compiled_.scene();
    for (size_t i = 0; i < scene.bodies.size(); ++i) {
        const KinematicTrack& animation = scene.bodies[i].animation;
        if (compiled_.bodies()[i].kinematic && activity_.present(i) && !animation.times_s.empty() &&
            t_s < animation.times_s.back())
            return true;
    }
    return false;
}

}  // namespace mwb
