#include "seek/GoalJson.h"

#include <nlohmann/json.hpp>

#include "query/ScreenBox.h"
#include "scene/BodyChanges.h"

namespace mwb {
namespace {

using nlohmann::json;

Matrix4 matrix(const json& box, const char* key, const std::string& where) {
    if (!box.contains(key) || !box[key].is_array())
        throw GoalError(where + ": \"" + key + "\" must be 16 numbers (a row-major 4x4 matrix)");
    std::vector<double> values;
    for (const json& row : box[key]) {
        if (row.is_array())
            for (const json& v : row) values.push_back(v.get<double>());
        else values.push_back(row.get<double>());
    }
    if (values.size() != 16) throw GoalError(where + ": \"" + key + "\" must be 16 numbers (a row-major 4x4 matrix)");
    Matrix4 m;
    std::copy(values.begin(), values.end(), m.begin());
    return m;
}

std::vector<double> numbers(const json& box, const char* key, size_t count, const std::string& where) {
    if (!box.contains(key) || !box[key].is_array() || box[key].size() != count)
        throw GoalError(where + ": \"" + key + "\" must be " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const json& v : box[key]) out.push_back(v.get<double>());
    return out;
}

std::vector<uint32_t> bodies_of(const json& box, const Scene& scene, const std::string& where) {
    std::vector<uint32_t> bodies;
    if (box.contains("bodies")) {
        for (const json& b : box["bodies"]) {
            const auto index = b.get<int64_t>();
            if (index < 0 || static_cast<size_t>(index) >= scene.bodies.size())
                throw GoalError(where + ": body " + std::to_string(index) + " is not in the library's scene (" +
                                std::to_string(scene.bodies.size()) + " bodies)");
            bodies.push_back(static_cast<uint32_t>(index));
        }
    } else if (box.contains("objects")) {
        for (const json& o : box["objects"]) {
            const std::string name = o.get<std::string>();
            size_t found = 0;
            for (size_t k = 0; k < scene.bodies.size(); ++k)
                if (object_of(scene.bodies[k]) == name) {
                    bodies.push_back(static_cast<uint32_t>(k));
                    ++found;
                }
            if (!found) throw GoalError(where + ": the library has no object '" + name + "'");
        }
    }
    if (bodies.empty()) throw GoalError(where + ": no bodies (give \"bodies\" or \"objects\")");
    return bodies;
}

// A direction given as 3 numbers, or `fallback` when the key is absent.
Vec3 direction(const json& part, const char* key, const Vec3& fallback, const std::string& where) {
    if (!part.contains(key)) return fallback;
    const std::vector<double> v = numbers(part, key, 3, where);
    return {v[0], v[1], v[2]};
}

// A part's "time_window" and "after", the same for boxes and orientation parts.
template <typename Spec>
void read_window_and_order(const json& part, const std::string& where, Spec& spec) {
    if (part.contains("time_window") && !part["time_window"].is_null()) {
        const std::vector<double> w = numbers(part, "time_window", 2, where);
        spec.time_window = std::make_pair(w[0], w[1]);
    }
    if (part.contains("after") && !part["after"].is_null()) spec.after = part["after"].get<int32_t>();
}

}  // namespace

std::vector<QueryBox> goal_from_json(const std::string& text, const Scene& scene) {
    json goal;
    try {
        goal = json::parse(text);
    } catch (const json::exception& error) {
        throw GoalError(std::string("the goal is not JSON: ") + error.what());
    }
    if (!goal.is_object() || !goal.contains("boxes") || !goal["boxes"].is_array())
        throw GoalError("the goal has no \"boxes\" list");
    std::vector<QueryBox> boxes;
    try {
        for (size_t k = 0; k < goal["boxes"].size(); ++k) {
            const json& b = goal["boxes"][k];
            const std::string where = "box " + std::to_string(k + 1);
            if (!b.is_object()) throw GoalError(where + " is not an object");
            ScreenBoxSpec spec;
            const std::vector<double> viewport = numbers(b, "viewport", 2, where);
            const std::vector<double> rect = numbers(b, "rect", 4, where);
            spec.view = matrix(b, "view", where);
            spec.projection = matrix(b, "projection", where);
            spec.viewport_width = viewport[0];
            spec.viewport_height = viewport[1];
            std::copy(rect.begin(), rect.end(), spec.rect.begin());
            spec.bodies = bodies_of(b, scene, where);
            spec.negative = b.value("negative", false);
            spec.swept = b.value("swept", false);
            read_window_and_order(b, where, spec);
            try {
                boxes.push_back(make_query_box(spec));
            } catch (const std::invalid_argument& error) {
                throw GoalError(where + " " + error.what());
            }
        }
    } catch (const json::exception& error) {
        throw GoalError(std::string("the goal is malformed: ") + error.what());
    }
    if (goal.contains("orientations")) {
        if (!goal["orientations"].is_array()) throw GoalError("the goal's \"orientations\" must be a list");
        try {
            for (size_t k = 0; k < goal["orientations"].size(); ++k) {
                const json& o = goal["orientations"][k];
                const std::string where = "orientation part " + std::to_string(k + 1);
                if (!o.is_object()) throw GoalError(where + " is not an object");
                OrientationPartSpec spec;
                spec.bodies = bodies_of(o, scene, where);
                spec.axis = direction(o, "axis", spec.axis, where);
                spec.target = direction(o, "target", spec.target, where);
                if (!o.contains("within_deg") || !o["within_deg"].is_number())
                    throw GoalError(where + ": \"within_deg\" must be a number of degrees");
                spec.within_deg = o["within_deg"].get<double>();
                spec.longer_than_s = o.value("longer_than_s", 0.0);
                spec.negative = o.value("negative", false);
                read_window_and_order(o, where, spec);
                try {
                    boxes.push_back(make_orientation_part(spec));
                } catch (const std::invalid_argument& error) {
                    throw GoalError(where + " " + error.what());
                }
            }
        } catch (const json::exception& error) {
            throw GoalError(std::string("the goal's orientation parts are malformed: ") + error.what());
        }
    }
    try {
        check_goal(boxes);
    } catch (const std::invalid_argument& error) {
        throw GoalError(error.what());
    }
    return boxes;
}

}  // namespace mwb
