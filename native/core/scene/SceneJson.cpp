#include "scene/SceneJson.h"

#include <atomic>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "scene/SceneValidation.h"

namespace mwb {
namespace {

using Json = nlohmann::json;
// Written with insertion order kept so that "format" and "version" come first for a human reader.
using OutJson = nlohmann::ordered_json;

constexpr const char* kFormatName = "mwb-scene";
constexpr int kMaxCompoundDepth = 32;
constexpr uint32_t kMaxUint32 = 0xffffffffu;

std::string index_suffix(size_t i) { return "[" + std::to_string(i) + "]"; }

// ---------------------------------------------------------------------------------------------
// Reading: every problem is collected as "<path>: <text>" and reading goes on where it can.

using Problems = std::vector<std::string>;

void report(Problems& problems, const std::string& where, const std::string& text) {
    problems.push_back((where.empty() ? "top level" : where) + ": " + text);
}

bool type_error(Problems& problems, const std::string& where, const std::string& expected, const Json& got) {
    report(problems, where, "expected " + expected + ", got " + got.type_name());
    return false;
}

bool read_value(const Json& j, const std::string& where, double& out, Problems& problems) {
    if (!j.is_number()) return type_error(problems, where, "a number", j);
    const double value = j.get<double>();
    // The parser refuses overflowing literals, but a document built in code may hold inf or NaN.
    if (!std::isfinite(value)) {
        report(problems, where, "expected a finite number, got " + j.dump());
        return false;
    }
    out = value;
    return true;
}

// Integers may also be written as integral floats (24.0); anything else outside [lo, hi] is refused.
bool read_integer(const Json& j, const std::string& where, int64_t lo, int64_t hi, int64_t& out, Problems& problems) {
    const std::string expected = "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!j.is_number()) return type_error(problems, where, expected, j);
    bool in_range = false;
    if (j.is_number_unsigned()) {
        const uint64_t value = j.get<uint64_t>();
        in_range = value <= static_cast<uint64_t>(hi) && static_cast<int64_t>(value) >= lo;
        out = in_range ? static_cast<int64_t>(value) : 0;
    } else if (j.is_number_integer()) {
        const int64_t value = j.get<int64_t>();
        in_range = value >= lo && value <= hi;
        out = value;
    } else {
        const double value = j.get<double>();
        in_range = std::floor(value) == value && value >= static_cast<double>(lo) && value <= static_cast<double>(hi);
        out = in_range ? static_cast<int64_t>(value) : 0;
    }
    if (!in_range) report(problems, where, "expected " + expected + ", got " + j.dump());
    return in_range;
}

bool read_value(const Json& j, const std::string& where, int& out, Problems& problems) {
    int64_t value = 0;
    if (!read_integer(j, where, INT32_MIN, INT32_MAX, value, problems)) return false;
    out = static_cast<int>(value);
    return true;
}

bool read_value(const Json& j, const std::string& where, uint32_t& out, Problems& problems) {
    int64_t value = 0;
    if (!read_integer(j, where, 0, kMaxUint32, value, problems)) return false;
    out = static_cast<uint32_t>(value);
    return true;
}

bool read_value(const Json& j, const std::string& where, bool& out, Problems& problems) {
    if (!j.is_boolean()) return type_error(problems, where, "true or false", j);
    out = j.get<bool>();
    return true;
}

bool read_value(const Json& j, const std::string& where, std::string& out, Problems& problems) {
    if (!j.is_string()) return type_error(problems, where, "a string", j);
    out = j.get<std::string>();
    return true;
}

// Fixed-length arrays: Vec3, Quat and per-axis flags.
template <typename T, size_t N>
bool read_value(const Json& j, const std::string& where, std::array<T, N>& out, Problems& problems) {
    const std::string expected = "an array of " + std::to_string(N) + (std::is_same_v<T, bool> ? " booleans" : " numbers");
    if (!j.is_array()) return type_error(problems, where, expected, j);
    if (j.size() != N) {
        report(problems, where, "expected " + expected + ", got " + std::to_string(j.size()) + " elements");
        return false;
    }
    std::array<T, N> values = out;
    bool ok = true;
    for (size_t i = 0; i < N; ++i) ok = read_value(j[i], where + index_suffix(i), values[i], problems) && ok;
    if (ok) out = values;
    return ok;
}

// Flat number arrays (mesh data, times); only the first bad element is reported.
template <typename T>
bool read_value(const Json& j, const std::string& where, std::vector<T>& out, Problems& problems) {
    if (!j.is_array()) return type_error(problems, where, "an array", j);
    std::vector<T> values(j.size());
    for (size_t i = 0; i < j.size(); ++i)
        if (!read_value(j[i], where + index_suffix(i), values[i], problems)) return false;
    out = std::move(values);
    return true;
}

// One JSON object: remembers which keys were read so unknown (misspelt) keys can be reported.
class ObjectReader {
public:
    ObjectReader(const Json& j, std::string path, Problems& problems)
        : json_(j), path_(std::move(path)), problems_(problems) {
        if (!j.is_object()) type_error(problems_, path_, "an object", j);
    }

    bool is_object() const { return json_.is_object(); }
    std::string path_of(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
    Problems& problems() { return problems_; }

    const Json* find(const std::string& key) {
        if (!json_.is_object()) return nullptr;
        used_.insert(key);
        auto it = json_.find(key);
        return it == json_.end() ? nullptr : &*it;
    }

    /// Leaves `out` unchanged (its Scene.h default) when the key is absent.
    template <typename T>
    bool optional(const std::string& key, T& out) {
        const Json* value = find(key);
        return value && read_value(*value, path_of(key), out, problems_);
    }

    template <typename T>
    bool required(const std::string& key, T& out) {
        const Json* value = find(key);
        if (!value && json_.is_object()) report(problems_, path_of(key), "missing required field");
        return value && read_value(*value, path_of(key), out, problems_);
    }

    void report_unknown_keys(const std::string& context = "") {
        if (!json_.is_object()) return;
        for (auto it = json_.begin(); it != json_.end(); ++it)
            if (!used_.count(it.key())) report(problems_, path_, "unknown field '" + it.key() + "'" + context);
    }

private:
    const Json& json_;
    std::string path_;
    Problems& problems_;
    std::set<std::string> used_;
};

template <typename Enum>
void read_enum(ObjectReader& object, const char* key, const char* what, const std::vector<Enum>& all,
               bool (*parse)(const std::string&, Enum&), Enum& out, bool& known) {
    std::string text;
    known = false;
    if (!object.required(key, text)) return;
    known = parse(text, out);
    if (known) return;
    std::string names;
    for (Enum value : all) names += (names.empty() ? "" : ", ") + std::string(to_string(value));
    report(object.problems(), object.path_of(key), "unknown " + std::string(what) + " '" + text + "' (expected one of " + names + ")");
}

// Reads a nested object member with `read`; absent members keep their defaults.
template <typename Fn>
void read_member(ObjectReader& parent, const std::string& key, Fn read) {
    if (const Json* j = parent.find(key)) {
        ObjectReader child(*j, parent.path_of(key), parent.problems());
        read(child);
        child.report_unknown_keys();
    }
}

void read_transform(ObjectReader& object, Transform& out) {
    object.optional("location", out.location);
    object.optional("rotation", out.rotation);
}

void read_shape(ObjectReader& object, Shape& out, int depth);

void read_children(ObjectReader& object, Shape& out, int depth) {
    const Json* children = object.find("children");
    if (!children) return;
    const std::string path = object.path_of("children");
    if (!children->is_array()) return void(type_error(object.problems(), path, "an array of shapes", *children));
    if (depth >= kMaxCompoundDepth)
        return report(object.problems(), path, "compounds nest deeper than " + std::to_string(kMaxCompoundDepth) + " levels");
    out.children.resize(children->size());
    for (size_t i = 0; i < children->size(); ++i) {
        ObjectReader child((*children)[i], path + index_suffix(i), object.problems());
        read_member(child, "offset", [&](ObjectReader& o) { read_transform(o, out.children[i].offset); });
        read_shape(child, out.children[i], depth + 1);
    }
}

// Only the fields a shape type uses are accepted, so a stray "radius_m" on a BOX is caught.
void read_shape(ObjectReader& object, Shape& out, int depth) {
    static const std::vector<ShapeType> kAll{ShapeType::Box,        ShapeType::Sphere, ShapeType::Capsule,
                                             ShapeType::Cylinder,   ShapeType::Cone,   ShapeType::ConvexHull,
                                             ShapeType::Mesh,       ShapeType::Compound};
    bool known = false;
    read_enum(object, "type", "shape type", kAll, parse_shape_type, out.type, known);
    if (!known) return;
    switch (out.type) {
        case ShapeType::Box: object.optional("half_extents_m", out.half_extents_m); break;
        case ShapeType::Sphere: object.optional("radius_m", out.radius_m); break;
        case ShapeType::Capsule:
        case ShapeType::Cylinder:
        case ShapeType::Cone:
            object.optional("radius_m", out.radius_m);
            object.optional("height_m", out.height_m);
            break;
        case ShapeType::ConvexHull: object.optional("vertices_m", out.vertices_m); break;
        case ShapeType::Mesh:
            object.optional("vertices_m", out.vertices_m);
            object.optional("triangles", out.triangles);
            break;
        case ShapeType::Compound: read_children(object, out, depth); break;
    }
    object.report_unknown_keys(std::string(" for a ") + to_string(out.type) + " shape");
}

void read_animation(ObjectReader& object, KinematicTrack& out) {
    object.optional("times_s", out.times_s);
    const Json* transforms = object.find("transforms");
    if (!transforms) return;
    const std::string path = object.path_of("transforms");
    if (!transforms->is_array()) return void(type_error(object.problems(), path, "an array of transforms", *transforms));
    out.transforms.resize(transforms->size());
    for (size_t i = 0; i < transforms->size(); ++i) {
        ObjectReader t((*transforms)[i], path + index_suffix(i), object.problems());
        read_transform(t, out.transforms[i]);
        t.report_unknown_keys();
    }
}

void read_variation(ObjectReader& o, VariationRanges& v) {
    o.optional("location_min_m", v.location_min_m);
    o.optional("location_max_m", v.location_max_m);
    o.optional("rotation_min_rad", v.rotation_min_rad);
    o.optional("rotation_max_rad", v.rotation_max_rad);
    o.optional("linear_velocity_min", v.linear_velocity_min);
    o.optional("linear_velocity_max", v.linear_velocity_max);
    o.optional("angular_velocity_min", v.angular_velocity_min);
    o.optional("angular_velocity_max", v.angular_velocity_max);
    o.optional("mass_scale_min", v.mass_scale_min);
    o.optional("mass_scale_max", v.mass_scale_max);
    o.optional("friction_scale_min", v.friction_scale_min);
    o.optional("friction_scale_max", v.friction_scale_max);
    o.optional("restitution_scale_min", v.restitution_scale_min);
    o.optional("restitution_scale_max", v.restitution_scale_max);
}

// "body 'Cube' (bodies[3])" when the element has a usable name, else "bodies[3]".
std::string element_label(const Json& j, const char* kind, const std::string& path) {
    if (j.is_object()) {
        auto name = j.find("name");
        if (name != j.end() && name->is_string() && !name->get_ref<const std::string&>().empty())
            return std::string(kind) + " '" + name->get<std::string>() + "' (" + path + ")";
    }
    return path;
}

void read_body(ObjectReader& o, Body& b) {
    static const std::vector<BodyType> kAll{BodyType::Active, BodyType::Passive};
    bool known = false;
    o.required("name", b.name);
    o.optional("object", b.object);
    read_enum(o, "type", "body type", kAll, parse_body_type, b.type, known);
    o.optional("kinematic", b.kinematic);
    o.optional("animated_until_s", b.animated_until_s);
    o.optional("enabled", b.enabled);
    if (const Json* shape = o.find("shape")) {
        ObjectReader reader(*shape, o.path_of("shape"), o.problems());
        read_shape(reader, b.shape, 0);
    } else if (o.is_object()) {
        report(o.problems(), o.path_of("shape"), "missing required field");
    }
    o.optional("mass_kg", b.mass_kg);
    o.optional("friction", b.friction);
    o.optional("restitution", b.restitution);
    o.optional("use_margin", b.use_margin);
    o.optional("collision_margin_m", b.collision_margin_m);
    o.optional("linear_damping", b.linear_damping);
    o.optional("angular_damping", b.angular_damping);
    read_member(o, "deactivation", [&](ObjectReader& d) {
        d.optional("enabled", b.deactivation.enabled);
        d.optional("start_deactivated", b.deactivation.start_deactivated);
        d.optional("linear_speed", b.deactivation.linear_speed);
        d.optional("angular_speed", b.deactivation.angular_speed);
    });
    o.optional("collision_collections", b.collision_collections);
    read_member(o, "initial", [&](ObjectReader& t) { read_transform(t, b.initial); });
    o.optional("initial_linear_velocity", b.initial_linear_velocity);
    o.optional("initial_angular_velocity", b.initial_angular_velocity);
    b.has_center_of_mass = o.optional("center_of_mass_local_m", b.center_of_mass_local_m);
    read_member(o, "animation", [&](ObjectReader& a) { read_animation(a, b.animation); });
    read_member(o, "variation", [&](ObjectReader& v) { read_variation(v, b.variation); });
}

void read_limits(ObjectReader& o, AxisLimits& limits) {
    o.optional("enabled", limits.enabled);
    o.optional("lower", limits.lower);
    o.optional("upper", limits.upper);
}

void read_springs(ObjectReader& o, AxisSprings& springs) {
    o.optional("enabled", springs.enabled);
    o.optional("stiffness", springs.stiffness);
    o.optional("damping", springs.damping);
}

void read_constraint(ObjectReader& o, Constraint& c) {
    static const std::vector<ConstraintType> kAll{
        ConstraintType::Fixed,   ConstraintType::Point,         ConstraintType::Hinge, ConstraintType::Slider,
        ConstraintType::Piston,  ConstraintType::Generic,       ConstraintType::GenericSpring,
        ConstraintType::Motor};
    bool known = false;
    o.required("name", c.name);
    read_enum(o, "type", "constraint type", kAll, parse_constraint_type, c.type, known);
    o.optional("body_a", c.body_a);
    o.optional("body_b", c.body_b);
    o.optional("enabled", c.enabled);
    o.optional("disable_collisions", c.disable_collisions);
    read_member(o, "frame", [&](ObjectReader& t) { read_transform(t, c.frame); });
    o.optional("breakable", c.breakable);
    o.optional("breaking_threshold", c.breaking_threshold);
    read_member(o, "linear_limits", [&](ObjectReader& l) { read_limits(l, c.linear_limits); });
    read_member(o, "angular_limits", [&](ObjectReader& l) { read_limits(l, c.angular_limits); });
    read_member(o, "linear_springs", [&](ObjectReader& s) { read_springs(s, c.linear_springs); });
    read_member(o, "angular_springs", [&](ObjectReader& s) { read_springs(s, c.angular_springs); });
    o.optional("motor_linear_enabled", c.motor_linear_enabled);
    o.optional("motor_angular_enabled", c.motor_angular_enabled);
    o.optional("motor_linear_target_velocity", c.motor_linear_target_velocity);
    o.optional("motor_linear_max_impulse", c.motor_linear_max_impulse);
    o.optional("motor_angular_target_velocity", c.motor_angular_target_velocity);
    o.optional("motor_angular_max_impulse", c.motor_angular_max_impulse);
}

void read_world(ObjectReader& o, WorldSettings& w) {
    o.optional("gravity", w.gravity);
    o.optional("time_scale", w.time_scale);
    o.optional("substeps_per_frame", w.substeps_per_frame);
    o.optional("solver_iterations", w.solver_iterations);
    o.optional("frame_start", w.frame_start);
    o.optional("frame_end", w.frame_end);
    o.optional("fps", w.fps);
}

template <typename T>
void read_list(ObjectReader& top, const char* key, const char* kind, std::vector<T>& out,
               const std::function<void(ObjectReader&, T&)>& read) {
    const Json* list = top.find(key);
    if (!list) return;
    if (!list->is_array()) return void(type_error(top.problems(), key, "an array", *list));
    out.resize(list->size());
    for (size_t i = 0; i < list->size(); ++i) {
        const Json& element = (*list)[i];
        ObjectReader reader(element, element_label(element, kind, key + index_suffix(i)), top.problems());
        read(reader, out[i]);
        reader.report_unknown_keys();
    }
}

// A file of another format or a newer version is refused outright: reading on would only bury
// the real reason under a pile of confusing field errors.
void check_format(ObjectReader& top) {
    const Json* format_value = top.find("format");
    if (!format_value || !format_value->is_string() || format_value->get<std::string>() != kFormatName)
        throw SceneError(std::string("format: expected \"") + kFormatName + "\", got " +
                         (format_value ? format_value->dump() : std::string("nothing")) +
                         "; this is not a Many-Worlds Browser scene");
    const Json* version_value = top.find("version");
    if (!version_value) throw SceneError("version: missing required field");
    Problems problems;
    int version = 0;
    if (!read_value(*version_value, "version", version, problems)) throw SceneError(problems.front());
    if (version > kSceneJsonVersion)
        throw SceneError("version: this scene uses format version " + std::to_string(version) +
                         ", newer than the " + std::to_string(kSceneJsonVersion) +
                         " this build reads; update Many-Worlds Browser");
    if (version < 1) throw SceneError("version: expected 1 or later, got " + std::to_string(version));
}

Scene read_scene(const Json& document, Problems& problems) {
    Scene scene;
    if (!document.is_object()) {
        throw SceneError(std::string("scene JSON: expected an object at the top level, got ") + document.type_name());
    }
    ObjectReader top(document, "", problems);
    check_format(top);
    top.optional("name", scene.name);
    read_member(top, "world", [&](ObjectReader& w) { read_world(w, scene.world); });
    read_list<Body>(top, "bodies", "body", scene.bodies, read_body);
    read_list<Constraint>(top, "constraints", "constraint", scene.constraints, read_constraint);
    top.report_unknown_keys();
    return scene;
}

std::string join_lines(const Problems& lines) {
    std::string text;
    for (const std::string& line : lines) text += (text.empty() ? "" : "\n") + line;
    return text;
}

// nlohmann's messages start with "[json.exception.parse_error.101] "; the rest is what users need.
std::string without_exception_tag(const char* what) {
    std::string text = what;
    const size_t end = text.find("] ");
    return text.rfind("[json.exception.", 0) == 0 && end != std::string::npos ? text.substr(end + 2) : text;
}

// ---------------------------------------------------------------------------------------------
// Writing: every field of Scene.h, except shape fields the shape type does not use.

OutJson transform_json(const Transform& t) { return {{"location", t.location}, {"rotation", t.rotation}}; }

OutJson shape_json(const Shape& shape) {
    OutJson j{{"type", to_string(shape.type)}};
    switch (shape.type) {
        case ShapeType::Box: j["half_extents_m"] = shape.half_extents_m; break;
        case ShapeType::Sphere: j["radius_m"] = shape.radius_m; break;
        case ShapeType::Capsule:
        case ShapeType::Cylinder:
        case ShapeType::Cone:
            j["radius_m"] = shape.radius_m;
            j["height_m"] = shape.height_m;
            break;
        case ShapeType::ConvexHull: j["vertices_m"] = shape.vertices_m; break;
        case ShapeType::Mesh:
            j["vertices_m"] = shape.vertices_m;
            j["triangles"] = shape.triangles;
            break;
        case ShapeType::Compound: {
            OutJson children = OutJson::array();
            for (const Shape& child : shape.children) {
                OutJson c = shape_json(child);
                c["offset"] = transform_json(child.offset);
                children.push_back(std::move(c));
            }
            j["children"] = std::move(children);
            break;
        }
    }
    return j;
}

OutJson variation_json(const VariationRanges& v) {
    return {{"location_min_m", v.location_min_m},
            {"location_max_m", v.location_max_m},
            {"rotation_min_rad", v.rotation_min_rad},
            {"rotation_max_rad", v.rotation_max_rad},
            {"linear_velocity_min", v.linear_velocity_min},
            {"linear_velocity_max", v.linear_velocity_max},
            {"angular_velocity_min", v.angular_velocity_min},
            {"angular_velocity_max", v.angular_velocity_max},
            {"mass_scale_min", v.mass_scale_min},
            {"mass_scale_max", v.mass_scale_max},
            {"friction_scale_min", v.friction_scale_min},
            {"friction_scale_max", v.friction_scale_max},
            {"restitution_scale_min", v.restitution_scale_min},
            {"restitution_scale_max", v.restitution_scale_max}};
}

OutJson body_json(const Body& b) {
    OutJson j{{"name", b.name},
              {"type", to_string(b.type)},
              {"kinematic", b.kinematic},
              {"enabled", b.enabled},
              {"shape", shape_json(b.shape)},
              {"mass_kg", b.mass_kg},
              {"friction", b.friction},
              {"restitution", b.restitution},
              {"use_margin", b.use_margin},
              {"collision_margin_m", b.collision_margin_m},
              {"linear_damping", b.linear_damping},
              {"angular_damping", b.angular_damping},
              {"collision_collections", b.collision_collections},
              {"initial", transform_json(b.initial)},
              {"initial_linear_velocity", b.initial_linear_velocity},
              {"initial_angular_velocity", b.initial_angular_velocity}};
    if (!b.object.empty()) j["object"] = b.object;
    if (b.animated_until_s > 0) j["animated_until_s"] = b.animated_until_s;
    if (b.has_center_of_mass) j["center_of_mass_local_m"] = b.center_of_mass_local_m;
    if (b.deactivation.enabled || b.deactivation.start_deactivated)
        j["deactivation"] = {{"enabled", b.deactivation.enabled},
                             {"start_deactivated", b.deactivation.start_deactivated},
                             {"linear_speed", b.deactivation.linear_speed},
                             {"angular_speed", b.deactivation.angular_speed}};
    if (!b.animation.times_s.empty() || !b.animation.transforms.empty()) {
        OutJson transforms = OutJson::array();
        for (const Transform& t : b.animation.transforms) transforms.push_back(transform_json(t));
        j["animation"] = {{"times_s", b.animation.times_s}, {"transforms", std::move(transforms)}};
    }
    j["variation"] = variation_json(b.variation);
    return j;
}

OutJson limits_json(const AxisLimits& l) { return {{"enabled", l.enabled}, {"lower", l.lower}, {"upper", l.upper}}; }
OutJson springs_json(const AxisSprings& s) {
    return {{"enabled", s.enabled}, {"stiffness", s.stiffness}, {"damping", s.damping}};
}

OutJson constraint_json(const Constraint& c) {
    return {{"name", c.name},
            {"type", to_string(c.type)},
            {"body_a", c.body_a},
            {"body_b", c.body_b},
            {"enabled", c.enabled},
            {"disable_collisions", c.disable_collisions},
            {"frame", transform_json(c.frame)},
            {"breakable", c.breakable},
            {"breaking_threshold", c.breaking_threshold},
            {"linear_limits", limits_json(c.linear_limits)},
            {"angular_limits", limits_json(c.angular_limits)},
            {"linear_springs", springs_json(c.linear_springs)},
            {"angular_springs", springs_json(c.angular_springs)},
            {"motor_linear_enabled", c.motor_linear_enabled},
            {"motor_angular_enabled", c.motor_angular_enabled},
            {"motor_linear_target_velocity", c.motor_linear_target_velocity},
            {"motor_linear_max_impulse", c.motor_linear_max_impulse},
            {"motor_angular_target_velocity", c.motor_angular_target_velocity},
            {"motor_angular_max_impulse", c.motor_angular_max_impulse}};
}

OutJson world_json(const WorldSettings& w) {
    return {{"gravity", w.gravity},
            {"time_scale", w.time_scale},
            {"substeps_per_frame", w.substeps_per_frame},
            {"solver_iterations", w.solver_iterations},
            {"frame_start", w.frame_start},
            {"frame_end", w.frame_end},
            {"fps", w.fps}};
}

}  // namespace

namespace {
std::atomic<uint64_t> g_scene_parses{0};
}  // namespace

uint64_t scene_parses_in_this_process() { return g_scene_parses.load(); }

Scene scene_from_json(const std::string& json_text) {
    ++g_scene_parses;
    Json document;
    try {
        document = Json::parse(json_text);
    } catch (const Json::exception& error) {
        // Syntax errors carry the line and column; numbers too large for a double ("1e999") do not.
        throw SceneError("scene JSON is malformed: " + without_exception_tag(error.what()));
    }
    Problems problems;
    Scene scene;
    try {
        scene = read_scene(document, problems);
    } catch (const Json::exception& error) {
        // Every access above checks types first; this only guards against a reader bug.
        throw SceneError("scene JSON could not be read: " + without_exception_tag(error.what()));
    }
    for (std::string& line : validate_scene(scene)) problems.push_back(std::move(line));
    if (!problems.empty()) throw SceneError(join_lines(problems));
    return scene;
}

std::string scene_to_json(const Scene& scene) {
    OutJson bodies = OutJson::array();
    for (const Body& body : scene.bodies) bodies.push_back(body_json(body));
    OutJson constraints = OutJson::array();
    for (const Constraint& constraint : scene.constraints) constraints.push_back(constraint_json(constraint));
    const OutJson document{{"format", kFormatName},
                           {"version", kSceneJsonVersion},
                           {"name", scene.name},
                           {"world", world_json(scene.world)},
                           {"bodies", std::move(bodies)},
                           {"constraints", std::move(constraints)}};
    try {
        return document.dump();
    } catch (const OutJson::exception& error) {
        // Names that are not valid UTF-8 cannot be stored in JSON.
        throw SceneError("scene cannot be written as JSON: " + without_exception_tag(error.what()));
    }
}

Scene load_scene_file(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw SceneError("scene file '" + path + "': cannot be opened");
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) throw SceneError("scene file '" + path + "': read error");
    try {
        return scene_from_json(text.str());
    } catch (const SceneError& error) {
        throw SceneError("scene file '" + path + "':\n" + error.what());
    }
}

}  // namespace mwb
