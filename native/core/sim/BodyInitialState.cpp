#include "sim/BodyInitialState.h"

namespace mwb {

std::vector<BodyInitialState> draw_initial_states(const Scene& scene, PortableRandom& random) {
    std::vector<BodyInitialState> states;
    states.reserve(scene.bodies.size());
    for (const Body& body : scene.bodies) {
        const VariationRanges& v = body.variation;
        BodyInitialState s;
        Vec3 offset, euler, lin, ang;
        for (int k = 0; k < 3; ++k) offset[k] = random.uniform(v.location_min_m[k], v.location_max_m[k]);
        for (int k = 0; k < 3; ++k) euler[k] = random.uniform(v.rotation_min_rad[k], v.rotation_max_rad[k]);
        for (int k = 0; k < 3; ++k) lin[k] = random.uniform(v.linear_velocity_min[k], v.linear_velocity_max[k]);
        for (int k = 0; k < 3; ++k) ang[k] = random.uniform(v.angular_velocity_min[k], v.angular_velocity_max[k]);
        const double mass_scale = random.uniform(v.mass_scale_min, v.mass_scale_max);
        const double friction_scale = random.uniform(v.friction_scale_min, v.friction_scale_max);
        const double restitution_scale = random.uniform(v.restitution_scale_min, v.restitution_scale_max);
        s.pose.location = add(body.initial.location, offset);
        s.pose.rotation = quat_normalized(quat_multiply(quat_from_euler_xyz(euler), body.initial.rotation));
        s.linear_velocity = add(body.initial_linear_velocity, lin);
        s.angular_velocity = add(body.initial_angular_velocity, ang);
        s.mass_kg = body.mass_kg * mass_scale;
        s.friction = body.friction * friction_scale;
        s.restitution = body.restitution * restitution_scale;
        states.push_back(s);
    }
    return states;
}

}  // namespace mwb
