#pragma once
// A scene revision record: the library's scene after bodies were added to some of its worlds.
// Revision r's scene starts with revision r-1's bodies in the same order (revision 0 is the run
// header's scene), so a body's index never changes; worlds say which bodies they have.
#include <cstdint>
#include <string>
#include <vector>

namespace mwb {

/// Record payload layout versions for scene revisions; a value never changes meaning.
constexpr uint32_t kSceneRevisionRecordVersion = 1;

struct SceneRevision {
    uint32_t revision = 0;  ///< 1 for the first revision after the header's scene
    std::string scene_json;
};

std::vector<uint8_t> encode_scene_revision(const SceneRevision& revision);
/// Throws LibraryError naming `where` on a malformed payload.
SceneRevision decode_scene_revision(const uint8_t* data, size_t size, const std::string& where);

/// Names of the scene's bodies in order. Throws SceneError for an invalid scene.
std::vector<std::string> scene_body_names(const std::string& scene_json);

}  // namespace mwb
