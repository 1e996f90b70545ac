#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "scene/BodyChanges.h"
#include "scene/SceneJson.h"
#include "scene/SceneValidation.h"
#include "sim/SimulationParameters.h"

namespace py = pybind11;

namespace mwb::python {

void bind_scene(py::module_& m) {
    py::register_exception<SceneError>(m, "SceneError", PyExc_ValueError);

    py::enum_<BodyRole>(m, "BodyRole", "What the simulation does with a body (scene/Scene.h body_role).")
        .value("SIMULATED", BodyRole::Simulated, "moved by physics, and perturbed")
        .value("ANIMATED", BodyRole::Animated, "follows its animation throughout")
        .value("STATIC", BodyRole::Static, "passive and not animated: never moves")
        .value("DISABLED", BodyRole::Disabled, "active with Dynamic off: stays where it is");
    m.def(
        "body_role",
        [](bool passive, bool enabled, bool animated_throughout) {
            Body body;
            body.type = passive ? BodyType::Passive : BodyType::Active;
            body.enabled = enabled;
            body.kinematic = animated_throughout;
            return body_role(body);
        },
        py::arg("passive"), py::arg("enabled"), py::arg("animated_throughout"),
        "The role the engine gives a body of these settings (Blender's PASSIVE type, Dynamic, and\n"
        "Animated for the whole run), for objects not exported yet.");

    py::class_<Scene>(m, "Scene", "A rigid-body scene in Blender's units (metres, kg, s, Z up).")
        .def_static("from_json", &scene_from_json, py::arg("text"),
                    "Parse and validate scene JSON; raises SceneError naming every problem.")
        .def_static("load", &load_scene_file, py::arg("path"))
        .def("to_json", &scene_to_json)
        .def_readonly("name", &Scene::name)
        .def_property_readonly("body_names",
                               [](const Scene& s) {
                                   std::vector<std::string> names;
                                   for (const Body& b : s.bodies) names.push_back(b.name);
                                   return names;
                               })
        .def_property_readonly("body_objects", [](const Scene& s) {
            std::vector<std::string> objects;
            for (const Body& b : s.bodies) objects.push_back(object_of(b));
            return objects;
        }, "per body: the object it stands for (an object changed after sampling has a body per definition)")
        .def_property_readonly("frame_start", [](const Scene& s) { return s.world.frame_start; })
        .def_property_readonly("fps", [](const Scene& s) { return s.world.fps; })
        .def_property_readonly("body_roles", [](const Scene& s) {
            std::vector<BodyRole> roles;
            for (const Body& b : s.bodies) roles.push_back(body_role(b));
            return roles;
        }, "per body: its BodyRole")
        .def_property_readonly("simulated_bodies", [](const Scene& s) {
            std::vector<uint32_t> bodies;
            for (uint32_t i = 0; i < s.bodies.size(); ++i)
                if (body_role(s.bodies[i]) == BodyRole::Simulated) bodies.push_back(i);
            return bodies;
        }, "indices of the bodies the simulation moves (BodyRole.SIMULATED)")
        .def_property_readonly("constraint_names", [](const Scene& s) {
            std::vector<std::string> names;
            for (const Constraint& c : s.constraints) names.push_back(c.name);
            return names;
        });

    py::class_<SimulationParameters>(m, "SimulationParameters",
                                     "Run parameters; defaults follow the design (alpha 0.1, lobe n 50, 120 Hz).")
        .def(py::init<>())
        .def_readwrite("duration_s", &SimulationParameters::duration_s)
        .def_readwrite("stop_at_rest", &SimulationParameters::stop_at_rest)
        .def_readwrite("min_step_hz", &SimulationParameters::min_step_hz)
        .def_readwrite("record_hz", &SimulationParameters::record_hz)
        .def_readwrite("alpha_linear", &SimulationParameters::alpha_linear)
        .def_readwrite("alpha_angular", &SimulationParameters::alpha_angular)
        .def_readwrite("lobe_exponent", &SimulationParameters::lobe_exponent)
        .def_readwrite("impact_linear_factor", &SimulationParameters::impact_linear_factor)
        .def_readwrite("impact_angular_factor", &SimulationParameters::impact_angular_factor)
        .def_readwrite("rest_linear_speed", &SimulationParameters::rest_linear_speed)
        .def_readwrite("rest_angular_speed", &SimulationParameters::rest_angular_speed)
        .def_readwrite("rest_duration_s", &SimulationParameters::rest_duration_s)
        .def_readwrite("checkpoint_interval_s", &SimulationParameters::checkpoint_interval_s)
        .def_readwrite("max_speed_mps", &SimulationParameters::max_speed_mps)
        .def_readwrite("max_distance_m", &SimulationParameters::max_distance_m)
        .def_readwrite("perturb", &SimulationParameters::perturb)
        .def_readwrite("sleep", &SimulationParameters::sleep)
        .def_readwrite("sleep_linear_speed", &SimulationParameters::sleep_linear_speed)
        .def_readwrite("sleep_angular_speed", &SimulationParameters::sleep_angular_speed)
        .def_readwrite("sleep_delay_s", &SimulationParameters::sleep_delay_s);

    m.def("validate_scene_json",
          [](const std::string& text) -> std::vector<std::string> {
              try {
                  scene_from_json(text);
                  return {};
              } catch (const SceneError& error) {
                  std::vector<std::string> lines;
                  std::string all = error.what();
                  size_t start = 0;
                  for (size_t end; (end = all.find('\n', start)) != std::string::npos; start = end + 1)
                      lines.push_back(all.substr(start, end - start));
                  lines.push_back(all.substr(start));
                  return lines;
              }
          },
          py::arg("text"), "Every problem of a scene JSON text, one line each; empty if valid.");
}

}  // namespace mwb::python
