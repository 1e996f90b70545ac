#pragma once
// Scene <-> JSON. The JSON is what the Blender exporter writes and what library files embed.
#include <stdexcept>
#include <string>

#include "scene/Scene.h"

namespace mwb {

/// Thrown for malformed or invalid scene data; the message names every offending object and field.
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Parses and validates a scene. Throws SceneError listing every problem found.
Scene scene_from_json(const std::string& json_text);
/// Serializes a scene; scene_from_json(scene_to_json(s)) reproduces s exactly (doubles round-trip).
std::string scene_to_json(const Scene& scene);
/// Reads a scene file; errors name the file.
Scene load_scene_file(const std::string& path);

}  // namespace mwb
