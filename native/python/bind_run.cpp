// The questions a front end asks before it starts the engine, answered in this process, and the
// engine protocol's names, so the add-on and the command line read them from the one definition.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common/EngineProtocol.h"
#include "library/RunSettings.h"
#include "scene/SceneJson.h"

namespace py = pybind11;

namespace mwb::python {

void bind_run(py::module_& m) {
    py::class_<RunSettings>(m, "RunSettings",
                            "The settings of a sampling run a person chooses; the defaults are the product's.")
        .def(py::init([](uint64_t seed, py::object duration_s, py::object stop_at_rest, py::object alpha,
                         py::object position_error_m, py::object rotation_error_deg) {
                 RunSettings s;
                 s.seed = seed;
                 if (!duration_s.is_none()) s.duration_s = duration_s.cast<double>();
                 if (!stop_at_rest.is_none()) s.stop_at_rest = stop_at_rest.cast<bool>();
                 if (!alpha.is_none()) s.alpha = alpha.cast<double>();
                 if (!position_error_m.is_none()) s.position_error_m = position_error_m.cast<double>();
                 if (!rotation_error_deg.is_none()) s.rotation_error_deg = rotation_error_deg.cast<double>();
                 return s;
             }),
             py::arg("seed") = 0, py::arg("duration_s") = py::none(), py::arg("stop_at_rest") = py::none(),
             py::arg("alpha") = py::none(), py::arg("position_error_m") = py::none(),
             py::arg("rotation_error_deg") = py::none(), "Unset settings take the defaults.")
        .def_readwrite("seed", &RunSettings::seed)
        .def_readwrite("duration_s", &RunSettings::duration_s, "<= 0: the scene's frame range")
        .def_readwrite("stop_at_rest", &RunSettings::stop_at_rest)
        .def_readwrite("alpha", &RunSettings::alpha, "perturbation strength (fraction of |dv| and |dw|)")
        .def_readwrite("position_error_m", &RunSettings::position_error_m)
        .def_readwrite("rotation_error_deg", &RunSettings::rotation_error_deg)
        .def("__repr__", [](const RunSettings& s) {
            return "<RunSettings seed " + std::to_string(s.seed) + ", duration " + std::to_string(s.duration_s) +
                   " s, alpha " + std::to_string(s.alpha) + ">";
        });

    py::enum_<LibraryHolding>(m, "LibraryHolding", "What a library file says about a run about to go into it.")
        .value("NEW", LibraryHolding::New, "no library there yet: the run starts it")
        .value("SAME", LibraryHolding::Same, "it holds this run: new worlds are added to it")
        .value("OTHER", LibraryHolding::Other, "it holds another run: the engine refuses to sample into it");

    m.def(
        "run_hash",
        [](const std::string& scene_json, const RunSettings& settings) {
            return run_hash(run_header_for(scene_from_json(scene_json), settings));
        },
        py::arg("scene_json"), py::arg("settings"),
        "The run hash a `sample` of this scene JSON with these settings writes (16 hex digits).");
    m.def(
        "library_holds_run",
        [](const std::string& library, const std::string& scene_json, const RunSettings& settings) {
            const RunHeader run = run_header_for(scene_from_json(scene_json), settings);
            py::gil_scoped_release release;
            return library_holding(library, run);
        },
        py::arg("library"), py::arg("scene_json"), py::arg("settings"),
        "Whether the library at `library` holds the run of this scene JSON and settings (LibraryHolding); reads\n"
        "only the file's header. Raises SceneError for a bad scene, LibraryError for a damaged file.");
    m.def(
        "run_header",
        [](const std::string& scene_json, const RunSettings& settings) {
            return run_header_for(scene_from_json(scene_json), settings);
        },
        py::arg("scene_json"), py::arg("settings"),
        "The LibraryHeader a `sample` of this scene JSON with these settings writes (engine_build empty):\n"
        "parse the scene once, then ask library_holds_run of as many libraries as needed.");
    m.def(
        "library_holds_run",
        [](const std::string& library, const RunHeader& run) {
            py::gil_scoped_release release;
            return library_holding(library, run);
        },
        py::arg("library"), py::arg("run"), "The same, for a run_header already made.");

    py::enum_<EngineExit>(m, "EngineExit", "mwb-engine's exit status.")
        .value("OK", EngineExit::Ok)
        .value("FAILED", EngineExit::Failed)
        .value("USAGE", EngineExit::Usage)
        .value("INVALID_SCENE", EngineExit::InvalidScene)
        .value("BAD_LIBRARY", EngineExit::BadLibrary)
        .value("CANCELLED", EngineExit::Cancelled);
    py::module_ protocol = m.def_submodule("engine_protocol", "mwb-engine's events (common/EngineProtocol.h).");
    protocol.attr("VERSION") = kEngineProtocolVersion;
    protocol.attr("EVENTS") = py::tuple(py::cast(engine_event_names()));
    protocol.attr("ERROR_CODES") = py::tuple(py::cast(engine_error_code_names()));
    protocol.attr("WARNING_CODES") = py::tuple(py::cast(engine_warning_code_names()));
}

}  // namespace mwb::python
