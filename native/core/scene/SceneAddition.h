#pragma once
// Bodies added to a library's scene after sampling: taken by name from a newer export of the
// same scene and appended, so the indices of the bodies already there never change.
#include <string>
#include <vector>

#include "scene/SceneJson.h"

namespace mwb {

/// Appends the bodies of `source` called `names` to `scene`, with every constraint of `source`
/// that involves one of them (its other body must then be in `scene`). A name `scene` already has
/// (added to other worlds before) is kept if `source` defines it the same way. Returns the scene
/// indices of `names` in order. Throws SceneError naming the body or constraint on any conflict.
std::vector<uint32_t> append_bodies(Scene& scene, const Scene& source, const std::vector<std::string>& names);

}  // namespace mwb
