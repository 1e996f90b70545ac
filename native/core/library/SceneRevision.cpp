#include "library/SceneRevision.h"

#include "library/ByteIO.h"
#include "scene/SceneJson.h"

namespace mwb {

std::vector<uint8_t> encode_scene_revision(const SceneRevision& revision) {
    ByteWriter out;
    out.put(revision.revision);
    out.put_string(revision.scene_json);
    return std::move(out.bytes());
}

SceneRevision decode_scene_revision(const uint8_t* data, size_t size, const std::string& where) {
    ByteReader in(data, size, where);
    SceneRevision revision;
    revision.revision = in.get<uint32_t>();
    revision.scene_json = in.get_string();
    if (in.remaining() != 0) in.fail("unexpected trailing bytes");
    return revision;
}

std::vector<std::string> scene_body_names(const std::string& scene_json) {
    std::vector<std::string> names;
    for (const Body& body : scene_from_json(scene_json).bodies) names.push_back(body.name);
    return names;
}

}  // namespace mwb
