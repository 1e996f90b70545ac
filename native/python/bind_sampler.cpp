#include <cmath>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "library/LibraryWriter.h"
#include "refine/StoredWorldRefinement.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "sim/OdeRandom.h"
#include "sim/WorldSimulator.h"

namespace py = pybind11;

namespace mwb::python {
namespace {

// Copies a flat vector into a new numpy array of the given shape.
py::array_t<double> to_array(const std::vector<double>& data, std::vector<py::ssize_t> shape) {
    py::array_t<double> out(shape);
    std::copy(data.begin(), data.end(), out.mutable_data());
    return out;
}

py::dict contacts_as_arrays(const WorldResult& w) {
    const auto n = static_cast<py::ssize_t>(w.contacts.size());
    py::array_t<double> time({n}), impulse({n});
    py::array_t<int32_t> body({n}), other({n});
    for (py::ssize_t k = 0; k < n; ++k) {
        const ContactEvent& e = w.contacts[static_cast<size_t>(k)];
        time.mutable_at(k) = e.time_s;
        impulse.mutable_at(k) = e.impulse_ns;
        body.mutable_at(k) = e.body;
        other.mutable_at(k) = e.other;
    }
    py::dict d;
    d["time_s"] = time;
    d["body"] = body;
    d["other"] = other;
    d["impulse_ns"] = impulse;
    return d;
}

py::dict checkpoint_as_dict(const Checkpoint& c, double step_hz) {
    const auto n = static_cast<py::ssize_t>(c.bodies.size());
    py::array_t<double> position({n, py::ssize_t{3}}), orientation({n, py::ssize_t{4}});
    py::array_t<double> linear({n, py::ssize_t{3}}), angular({n, py::ssize_t{3}});
    for (py::ssize_t i = 0; i < n; ++i) {
        const BodyState& s = c.bodies[static_cast<size_t>(i)];
        for (py::ssize_t k = 0; k < 3; ++k) {
            position.mutable_at(i, k) = s.position_m[k];
            linear.mutable_at(i, k) = s.linear_velocity[k];
            angular.mutable_at(i, k) = s.angular_velocity[k];
        }
        for (py::ssize_t k = 0; k < 4; ++k) orientation.mutable_at(i, k) = s.orientation[k];
    }
    py::dict d;
    d["time_s"] = static_cast<double>(c.step_index) / step_hz;
    d["com_position_m"] = position;
    d["orientation"] = orientation;
    d["linear_velocity"] = linear;
    d["angular_velocity"] = angular;
    d["joint_broken"] = c.joint_broken;
    return d;
}

struct RefineResult {
    std::vector<uint64_t> children;
    uint64_t stored = 0, rejected = 0;
};

const char* status_name(WorldStatus s) {
    switch (s) {
        case WorldStatus::Ok: return "ok";
        case WorldStatus::Rejected: return "rejected";
        case WorldStatus::Cancelled: return "cancelled";
    }
    return "unknown";
}

}  // namespace

void bind_sampler(py::module_& m) {
    py::class_<WorldResult>(m, "World", "One sampled world and everything it recorded.")
        .def_readonly("world_index", &WorldResult::world_index)
        .def_readonly("seed", &WorldResult::seed)
        .def_property_readonly("status", [](const WorldResult& w) { return status_name(w.status); })
        .def_readonly("reject_reason", &WorldResult::reject_reason)
        .def_readonly("record_hz", &WorldResult::record_hz)
        .def_readonly("step_hz", &WorldResult::step_hz)
        .def_readonly("frame_count", &WorldResult::frame_count)
        .def_readonly("body_count", &WorldResult::body_count)
        .def_readonly("simulated_time_s", &WorldResult::simulated_time_s)
        .def_readonly("impacts_perturbed", &WorldResult::impacts_perturbed)
        .def_property_readonly("positions",
                               [](const WorldResult& w) {
                                   return to_array(w.positions_m, {w.body_count, w.frame_count, 3});
                               },
                               "float64 (bodies, frames, 3): object origins in metres, world frame")
        .def_property_readonly("orientations",
                               [](const WorldResult& w) {
                                   return to_array(w.orientations, {w.body_count, w.frame_count, 4});
                               },
                               "float64 (bodies, frames, 4): unit quaternions (w, x, y, z)")
        .def_property_readonly("rest_time_s", [](const WorldResult& w) { return to_array(w.rest_time_s, {w.body_count}); },
                               "float64 (bodies,): start of each body's final rest, or the end time")
        .def_property_readonly("contacts", &contacts_as_arrays,
                               "dict of equal-length arrays: time_s, body, other (-1: none), impulse_ns")
        .def_property_readonly("checkpoints",
                               [](const WorldResult& w) {
                                   py::list out;
                                   for (const Checkpoint& c : w.checkpoints) out.append(checkpoint_as_dict(c, w.step_hz));
                                   return out;
                               })
        .def_property_readonly("hash", &hash_world, "64-bit hash of everything recorded (determinism checks)");

    m.def(
        "sample",
        [](const Scene& scene, const SimulationParameters& parameters, uint64_t base_seed, uint64_t first_world,
           uint64_t world_count, int threads, const std::function<void(const WorldResult&)>& on_world) {
            CompiledScene compiled(scene, parameters);
            std::vector<WorldResult> worlds;
            worlds.reserve(world_count);
            {
                py::gil_scoped_release release;
                sample_worlds(compiled, base_seed, first_world, world_count, threads, [&](WorldResult&& w) {
                    if (on_world) {
                        py::gil_scoped_acquire acquire;
                        on_world(w);
                    }
                    worlds.push_back(std::move(w));
                });
            }
            std::sort(worlds.begin(), worlds.end(),
                      [](const WorldResult& a, const WorldResult& b) { return a.world_index < b.world_index; });
            return worlds;
        },
        py::arg("scene"), py::arg("parameters"), py::arg("base_seed"), py::arg("first_world"), py::arg("world_count"),
        py::arg("threads") = 0, py::arg("on_world") = nullptr,
        "Simulate worlds [first_world, first_world + world_count) in parallel with the GIL released.\n"
        "Returns them sorted by index; on_world(world) is called as each finishes (completion order).\n"
        "For scripting and tests: bulk sampling from Blender runs the mwb-engine executable instead.");

    py::register_exception<RefineError>(m, "RefineError", PyExc_ValueError);
    py::class_<RefineResult>(m, "RefineResult", "What a refinement in this process made.")
        .def_readonly("children", &RefineResult::children, "the new worlds' indices")
        .def_readonly("stored", &RefineResult::stored)
        .def_readonly("rejected", &RefineResult::rejected);
    m.def(
        "refine_stored_world",
        [](const std::string& library, uint64_t world, std::vector<uint32_t> bodies, double branch_time_s,
           uint64_t count, int threads, int64_t first_child) {
            RefineRequest request;
            request.parent_world = world;
            request.bodies = std::move(bodies);
            request.branch_time_s = branch_time_s;
            request.count = count;
            request.threads = threads;
            request.first_child = first_child;
            py::gil_scoped_release release;
            const LibraryReader reader(library);
            LibraryWriter writer(library, reader.header());
            const RefineOutcome outcome = refine_stored_world(reader, request, writer);
            RefineResult result;
            for (uint64_t k = 0; k < count; ++k) result.children.push_back(outcome.first_child + k);
            result.stored = outcome.statistics.worlds_ok;
            result.rejected = outcome.statistics.worlds_rejected;
            return result;
        },
        py::arg("library"), py::arg("world"), py::arg("bodies"), py::arg("branch_time_s"), py::arg("count"),
        py::arg("threads") = 0, py::arg("first_child") = -1,
        "Refine a stored world in this process (GIL released): append `count` children of `world` that re-simulate\n"
        "`bodies` from branch_time_s (snapped down to a recorded frame) to the library file. Returns a\n"
        "RefineResult. Raises RefineError when the request does not fit the library.");

    m.def("ode_random_calls_on_this_thread", &ode_random_calls_on_this_thread,
          "dRandInt calls on this thread that reached the engine's per-world generator.");
}

}  // namespace mwb::python
