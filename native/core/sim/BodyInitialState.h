#pragma once
// Each world starts its bodies in a state drawn from the scene's variation ranges.
#include <vector>

#include "scene/Scene.h"
#include "sim/PortableRandom.h"

namespace mwb {

/// A body's randomized starting state and material, object-origin frame.
struct BodyInitialState {
    Transform pose;
    Vec3 linear_velocity{0, 0, 0};
    Vec3 angular_velocity{0, 0, 0};
    double mass_kg = 1;
    double friction = 0.5;
    double restitution = 0;
};

/// Draws every body's initial state from its variation ranges. Always consumes the same number
/// of draws per body, so a body's draws never depend on other bodies' ranges.
std::vector<BodyInitialState> draw_initial_states(const Scene& scene, PortableRandom& random);

}  // namespace mwb
