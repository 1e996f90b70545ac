#include "scene/Scene.h"

#include <array>
#include <utility>

namespace mwb {
namespace {

constexpr std::array<std::pair<ShapeType, const char*>, 8> kShapeNames{{
    {ShapeType::Box, "BOX"},
    {ShapeType::Sphere, "SPHERE"},
    {ShapeType::Capsule, "CAPSULE"},
    {ShapeType::Cylinder, "CYLINDER"},
    {ShapeType::Cone, "CONE"},
    {ShapeType::ConvexHull, "CONVEX_HULL"},
    {ShapeType::Mesh, "MESH"},
    {ShapeType::Compound, "COMPOUND"},
}};
constexpr std::array<std::pair<BodyType, const char*>, 2> kBodyNames{{
    {BodyType::Active, "ACTIVE"},
    {BodyType::Passive, "PASSIVE"},
}};
constexpr std::array<std::pair<ConstraintType, const char*>, 8> kConstraintNames{{
    {ConstraintType::Fixed, "FIXED"},
    {ConstraintType::Point, "POINT"},
    {ConstraintType::Hinge, "HINGE"},
    {ConstraintType::Slider, "SLIDER"},
    {ConstraintType::Piston, "PISTON"},
    {ConstraintType::Generic, "GENERIC"},
    {ConstraintType::GenericSpring, "GENERIC_SPRING"},
    {ConstraintType::Motor, "MOTOR"},
}};

template <typename Enum, size_t N>
const char* name_of(const std::array<std::pair<Enum, const char*>, N>& table, Enum value) {
    for (const auto& [entry, name] : table)
        if (entry == value) return name;
    return "UNKNOWN";
}

template <typename Enum, size_t N>
bool value_of(const std::array<std::pair<Enum, const char*>, N>& table, const std::string& text,
              Enum& out) {
    for (const auto& [entry, name] : table) {
        if (text == name) {
            out = entry;
            return true;
        }
    }
    return false;
}

}  // namespace

int Scene::body_index(const std::string& body_name) const {
    for (size_t i = 0; i < bodies.size(); ++i)
        if (bodies[i].name == body_name) return static_cast<int>(i);
    return -1;
}

const char* to_string(ShapeType type) { return name_of(kShapeNames, type); }
const char* to_string(BodyType type) { return name_of(kBodyNames, type); }
const char* to_string(ConstraintType type) { return name_of(kConstraintNames, type); }
bool parse_shape_type(const std::string& text, ShapeType& out) { return value_of(kShapeNames, text, out); }
bool parse_body_type(const std::string& text, BodyType& out) { return value_of(kBodyNames, text, out); }
bool parse_constraint_type(const std::string& text, ConstraintType& out) {
    return value_of(kConstraintNames, text, out);
}

BodyRole body_role(const Body& body) {
    if (body.kinematic) return BodyRole::Animated;
    if (body.type == BodyType::Passive) return BodyRole::Static;
    return body.enabled ? BodyRole::Simulated : BodyRole::Disabled;
}

const char* to_string(BodyRole role) {
    switch (role) {
        case BodyRole::Simulated: return "simulated";
        case BodyRole::Animated: return "animated";
        case BodyRole::Static: return "static";
        case BodyRole::Disabled: return "disabled";
    }
    return "unknown";
}

}  // namespace mwb
