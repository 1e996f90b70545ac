#pragma once
// Changing which objects one world has, after sampling, on a library's scene: objects added are
// taken from a newer export of the scene and appended, so the indices of the bodies already there
// never change. An object whose definition changed (moved, new mass, ...) gets a body of its own
// for the new definition ("Ball#2", standing for object "Ball"); its earlier bodies stay for the
// worlds that have them.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/Scene.h"

namespace mwb {

/// A request that does not fit the world or the export; the message names every object at fault,
/// one per line.
struct SceneChangeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The object a body stands for: its `object`, or its name.
const std::string& object_of(const Body& body);

struct BodyChanges {
    std::vector<uint32_t> added;    ///< scene body indices the world gains
    std::vector<uint32_t> removed;  ///< scene body indices the world loses
    bool scene_grew = false;        ///< bodies or constraints were appended to the scene
};

/// Edits `scene` (a library's scene) for one world that has the bodies flagged in `present` (one
/// flag per scene body): `add` objects it lacks, `remove` objects it has, and `update` objects it
/// has to their definition in `source` (remove + add). Added and updated objects come from
/// `source`, with the constraints of `source` that involve them; an object defined as an earlier
/// body of the scene reuses that body. Throws SceneChangeError on any conflict.
BodyChanges change_bodies(Scene& scene, const std::vector<uint8_t>& present, const Scene& source,
                          const std::vector<std::string>& add, const std::vector<std::string>& remove,
                          const std::vector<std::string>& update);

}  // namespace mwb
