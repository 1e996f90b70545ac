#include "scene/BodyChanges.h"

#include <algorithm>
#include <type_traits>

#include "scene/SceneJson.h"

namespace mwb {
namespace {

// Two definitions are the same when they serialize the same (doubles round-trip exactly),
// whatever body name they are stored under.
std::string definition_of(Body body) {
    body.name.clear();
    body.object.clear();
    Scene single;
    single.bodies.push_back(std::move(body));
    return scene_to_json(single);
}

std::string definition_of(const Constraint& constraint) {
    Scene single;
    single.constraints.push_back(constraint);
    return scene_to_json(single);
}

// `base`, or `base#2`, `base#3`, ... : the first that `taken` does not hold.
template <typename Taken>
std::string unique_name(const std::string& base, Taken taken) {
    if (!taken(base)) return base;
    for (int k = 2;; ++k)
        if (!taken(base + "#" + std::to_string(k))) return base + "#" + std::to_string(k);
}

class WorldBodies {
public:
    WorldBodies(Scene& scene, const std::vector<uint8_t>& present) : scene_(scene), present_(present) {
        present_.resize(scene.bodies.size(), 0);
    }

    /// The body of `object` the world has, or -1.
    int present_body(const std::string& object) const {
        for (size_t i = 0; i < scene_.bodies.size(); ++i)
            if (present_[i] && object_of(scene_.bodies[i]) == object) return static_cast<int>(i);
        return -1;
    }

    /// The body that holds `definition` (an earlier one of its object, or a new one appended).
    uint32_t body_for(const Body& definition, bool& grew) {
        const std::string wanted = definition_of(definition);
        for (size_t i = 0; i < scene_.bodies.size(); ++i)
            if (object_of(scene_.bodies[i]) == definition.name && definition_of(scene_.bodies[i]) == wanted)
                return static_cast<uint32_t>(i);
        Body body = definition;
        body.name = unique_name(definition.name, [&](const std::string& n) { return scene_.body_index(n) >= 0; });
        if (body.name != definition.name) body.object = definition.name;
        scene_.bodies.push_back(std::move(body));
        present_.push_back(0);
        grew = true;
        return static_cast<uint32_t>(scene_.bodies.size() - 1);
    }

    void set_present(uint32_t body, bool present) { present_[body] = present ? 1 : 0; }

private:
    Scene& scene_;
    std::vector<uint8_t> present_;
};

}  // namespace

const std::string& object_of(const Body& body) { return body.object.empty() ? body.name : body.object; }

BodyChanges change_bodies(Scene& scene, const std::vector<uint8_t>& present, const Scene& source,
                          const std::vector<std::string>& add, const std::vector<std::string>& remove,
                          const std::vector<std::string>& update) {
    BodyChanges changes;
    std::vector<std::string> problems;
    WorldBodies world(scene, present);
    std::vector<std::string> taken_from_source;  // objects whose definition comes from `source`
    auto take = [&](const std::string& object, bool replacing) {
        const int in_source = source.body_index(object);
        const int now = world.present_body(object);
        if (in_source < 0) return problems.push_back("'" + object + "': not in the exported scene");
        if (!replacing && now >= 0) return problems.push_back("'" + object + "' is already in the world");
        if (replacing && now < 0) return problems.push_back("'" + object + "' is not in the world; add it instead");
        const Body& definition = source.bodies[static_cast<size_t>(in_source)];
        if (replacing && definition_of(scene.bodies[static_cast<size_t>(now)]) == definition_of(definition))
            return problems.push_back("'" + object + "' is unchanged");
        if (replacing) {
            changes.removed.push_back(static_cast<uint32_t>(now));
            world.set_present(static_cast<uint32_t>(now), false);
        }
        const uint32_t body = world.body_for(definition, changes.scene_grew);
        changes.added.push_back(body);
        world.set_present(body, true);
        taken_from_source.push_back(object);
    };
    for (const std::string& object : remove) {
        const int now = world.present_body(object);
        if (now < 0) {
            problems.push_back("'" + object + "' is not in the world");
            continue;
        }
        changes.removed.push_back(static_cast<uint32_t>(now));
        world.set_present(static_cast<uint32_t>(now), false);
    }
    for (const std::string& object : add) take(object, false);
    for (const std::string& object : update) take(object, true);
    // Constraints of the objects taken from the export, tied to the bodies the world now has.
    for (const Constraint& c : source.constraints) {
        auto taken = [&](const std::string& o) {
            return std::find(taken_from_source.begin(), taken_from_source.end(), o) != taken_from_source.end();
        };
        if (!taken(c.body_a) && !taken(c.body_b)) continue;
        Constraint tied = c;
        bool complete = true;
        for (std::string* end : {&tied.body_a, &tied.body_b}) {
            if (end->empty()) continue;
            const int body = world.present_body(*end);
            if (body < 0) {
                problems.push_back("constraint '" + c.name + "': '" + *end + "' is in neither the world nor the added objects");
                complete = false;
                continue;
            }
            *end = scene.bodies[static_cast<size_t>(body)].name;
        }
        if (!complete) continue;
        const std::string wanted = definition_of(tied);
        const bool known = std::any_of(scene.constraints.begin(), scene.constraints.end(), [&](const Constraint& k) {
            Constraint renamed = k;
            renamed.name = tied.name;
            return definition_of(renamed) == wanted && (k.name == tied.name || k.name.rfind(tied.name + "#", 0) == 0);
        });
        if (known) continue;
        tied.name = unique_name(tied.name, [&](const std::string& n) {
            return std::any_of(scene.constraints.begin(), scene.constraints.end(), [&](const Constraint& k) { return k.name == n; });
        });
        scene.constraints.push_back(std::move(tied));
        changes.scene_grew = true;
    }
    if (!problems.empty()) {
        std::string message;
        for (const std::string& p : problems) message += (message.empty() ? "" : "\n") + p;
        throw SceneChangeError(message);
    }
    return changes;
}

}  // namespace mwb
