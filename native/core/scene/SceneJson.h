#pragma once
// Scene <-> JSON. The JSON is what the Blender exporter writes and what library files embed.
// The schema ("mwb-scene", version 1) is described field by field in scene/SCENE_JSON.md; in short:
//   {"format": "mwb-scene", "version": 1, "name": str, "world": {...}, "bodies": [...],
//    "constraints": [...]}
// Field names are the Scene.h member names, enums are Blender's identifiers ("ACTIVE", "BOX",
// "GENERIC_SPRING"), Vec3 is [x, y, z], quaternions are [w, x, y, z], mesh data are flat arrays.
// Every field except format, version, a body's name/type/shape, a shape's type and a constraint's
// name/type is optional and defaults to the Scene.h value. Unknown fields are errors.
#include <stdexcept>
#include <string>

#include "scene/Scene.h"

namespace mwb {

/// The scene JSON format version this build writes and the newest it reads.
constexpr int kSceneJsonVersion = 1;

/// Thrown for malformed or invalid scene data; the message names every offending object and field,
/// one problem per line ("body 'Cube' (bodies[3]).mass_kg: expected a number, got string").
struct SceneError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Parses and validates (validate_scene) a scene. Throws SceneError listing every problem found;
/// malformed JSON gives the parser's line and column; another format or a newer version is refused.
Scene scene_from_json(const std::string& json_text);
/// How many times this process has parsed a scene (scene_from_json, load_scene_file): a run
/// reports it, so a test can hold the engine to one parse per process.
uint64_t scene_parses_in_this_process();
/// Serializes a scene as compact JSON; scene_from_json(scene_to_json(s)) reproduces s exactly
/// (doubles round-trip bit for bit), except shape fields unused by the shape's type, which are not
/// written and read back as defaults. Throws SceneError for strings that are not valid UTF-8.
std::string scene_to_json(const Scene& scene);
/// Reads a scene file; errors name the file.
Scene load_scene_file(const std::string& path);

}  // namespace mwb
