#include "scene/SceneAddition.h"

#include <algorithm>
#include <type_traits>

namespace mwb {
namespace {

// Two definitions are the same when they serialize the same (doubles round-trip exactly).
template <typename T>
std::string definition_of(const T& item) {
    Scene single;
    if constexpr (std::is_same_v<T, Body>) single.bodies.push_back(item);
    else single.constraints.push_back(item);
    return scene_to_json(single);
}

}  // namespace

std::vector<uint32_t> append_bodies(Scene& scene, const Scene& source, const std::vector<std::string>& names) {
    std::vector<uint32_t> indices;
    std::vector<std::string> problems;
    for (const std::string& name : names) {
        const int in_source = source.body_index(name);
        if (in_source < 0) {
            problems.push_back("body '" + name + "': not in the exported scene");
            continue;
        }
        const Body& body = source.bodies[static_cast<size_t>(in_source)];
        const int existing = scene.body_index(name);
        if (existing >= 0) {
            if (definition_of(scene.bodies[static_cast<size_t>(existing)]) != definition_of(body))
                problems.push_back("body '" + name + "': the library already has a different body of that name; "
                                   "rename the object to add it as a new body");
            indices.push_back(static_cast<uint32_t>(existing));
            continue;
        }
        indices.push_back(static_cast<uint32_t>(scene.bodies.size()));
        scene.bodies.push_back(body);
    }
    for (const Constraint& c : source.constraints) {
        const bool involved = std::find(names.begin(), names.end(), c.body_a) != names.end() ||
                              std::find(names.begin(), names.end(), c.body_b) != names.end();
        if (!involved) continue;
        for (const std::string& other : {c.body_a, c.body_b})
            if (!other.empty() && scene.body_index(other) < 0)
                problems.push_back("constraint '" + c.name + "': body '" + other + "' is in neither the library nor the added bodies");
        const auto same_name = std::find_if(scene.constraints.begin(), scene.constraints.end(),
                                            [&](const Constraint& k) { return k.name == c.name; });
        if (same_name == scene.constraints.end()) scene.constraints.push_back(c);
        else if (definition_of(*same_name) != definition_of(c))
            problems.push_back("constraint '" + c.name + "': the library already has a different constraint of that name");
    }
    if (!problems.empty()) {
        std::string message;
        for (const std::string& p : problems) message += (message.empty() ? "" : "\n") + p;
        throw SceneError(message);
    }
    return indices;
}

}  // namespace mwb
