#pragma once
// Checks a scene for what the simulator cannot run, naming each object and field.
#include <string>
#include <vector>

#include "scene/Scene.h"

namespace mwb {

/// Returns one human-readable line per problem ("body 'Cube': mass_kg must be > 0 for an ACTIVE
/// body, got 0"); empty when the scene can be simulated.
std::vector<std::string> validate_scene(const Scene& scene);

}  // namespace mwb
