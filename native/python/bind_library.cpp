#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "codec/CodecError.h"
#include "library/ByteIO.h"
#include "library/LibraryMerge.h"
#include "library/LibraryReader.h"
#include "library/PolylineGather.h"
#include "library/WorldDecoding.h"
#include "sim/PoseInterpolation.h"
#include "PyLibrary.h"

namespace py = pybind11;

namespace mwb::python {
namespace {

py::array_t<double> as_array(std::vector<double>&& data, std::vector<py::ssize_t> shape) {
    py::array_t<double> out(shape);
    std::copy(data.begin(), data.end(), out.mutable_data());
    return out;
}

// A world's stored metrics as Python sees them: per metric name, one value per scene body.
struct WorldMetrics {
    std::vector<std::string> names;
    std::map<std::string, std::vector<double>> values;

    const std::vector<double>& of(const std::string& name) const {
        const auto it = values.find(name);
        if (it == values.end()) throw py::key_error("no metric '" + name + "' (the world has: " + joined(names) + ")");
        return it->second;
    }
    static std::string joined(const std::vector<std::string>& names) {
        std::string text;
        for (const std::string& n : names) text += (text.empty() ? "" : ", ") + n;
        return text;
    }
};

// Rows of every per-body array: one per body of the library's scene now (a world made before
// bodies were added has fewer tracks).
size_t body_rows(const PyLibrary& l, const StoredWorld& world) {
    return std::max(l.reader().scene_body_count(), world.tracks.size());
}

// Per scene body: a track's value, or `absent` for bodies the world does not have.
template <typename T, typename F>
std::vector<T> per_body(const PyLibrary& l, const StoredWorld& world, T absent, F value) {
    std::vector<T> out(body_rows(l, world), absent);
    for (size_t t = 0; t < world.tracks.size(); ++t)
        if (world.tracks[t].present) out[t] = value(world.tracks[t], t);
    return out;
}

// (bodies, frames, width) of one world decoded by `decode` with the GIL released.
py::array_t<double> decoded(const PyLibrary& l, uint64_t w, std::vector<double> (*decode)(const StoredWorld&, size_t),
                            py::ssize_t width) {
    const StoredWorld& world = l.world(w);
    std::vector<double> data;
    {
        py::gil_scoped_release release;
        data = decode(world, l.reader().scene_body_count());
    }
    return as_array(std::move(data), {static_cast<py::ssize_t>(body_rows(l, world)), world.frame_count, width});
}

// (loc (n, frames, 3), rot (n, frames, 4)) of `bodies` (every body when None) at fractional
// recorded frames, as bake keys them and a preview shows them: decoded and interpolated here, so
// the tracks never cross into Python.
py::tuple world_poses(PyLibrary& l, uint64_t w, const std::vector<double>& at_frames,
                      const std::optional<std::vector<int64_t>>& bodies) {
    for (double f : at_frames)
        if (!std::isfinite(f)) throw py::value_error("frames must be finite");
    const PyLibrary::DecodedWorld& world = l.decoded_world(w);
    if (world.frames == 0) throw py::value_error("world " + std::to_string(w) + " has no frames");
    std::vector<size_t> rows;
    if (bodies) {
        for (int64_t b : *bodies) {
            if (b < 0 || static_cast<size_t>(b) >= world.rows)
                throw py::index_error("body " + std::to_string(b) + " is not in the library's scene (" +
                                      std::to_string(world.rows) + " bodies)");
            rows.push_back(static_cast<size_t>(b));
        }
    } else {
        for (size_t b = 0; b < world.rows; ++b) rows.push_back(b);
    }
    const auto n = static_cast<py::ssize_t>(at_frames.size()), count = static_cast<py::ssize_t>(rows.size());
    py::array_t<double> loc({count, n, py::ssize_t{3}}), rot({count, n, py::ssize_t{4}});
    double* out_loc = loc.mutable_data();
    double* out_rot = rot.mutable_data();
    {
        py::gil_scoped_release release;
        for (size_t k = 0; k < rows.size(); ++k)
            sample_recorded_poses(world.positions.data() + rows[k] * world.frames * 3,
                                  world.orientations.data() + rows[k] * world.frames * 4, 1, world.frames, at_frames,
                                  out_loc + k * at_frames.size() * 3, out_rot + k * at_frames.size() * 4);
    }
    return py::make_tuple(loc, rot);
}

// float32 (worlds, bodies, points, 3) of the chosen bodies' polylines, copied without the GIL.
py::array_t<float> gathered_polylines(const PyLibrary& l, const std::vector<uint64_t>& world_indices,
                                      const std::vector<int64_t>& bodies, int64_t stride) {
    if (stride < 1) throw py::value_error("stride must be at least 1, got " + std::to_string(stride));
    const size_t body_count = l.reader().scene_body_count();
    std::vector<uint32_t> rows;
    for (const int64_t body : bodies) {
        if (body < 0 || static_cast<size_t>(body) >= body_count)
            throw py::index_error("body " + std::to_string(body) + " out of range: the library has " +
                                  std::to_string(body_count) + " bodies");
        rows.push_back(static_cast<uint32_t>(body));
    }
    // Held from the first look-up on, so poll() cannot move the worlds while they are copied.
    const auto lock = l.read_lock();
    std::vector<const StoredWorld*> worlds;
    for (const uint64_t w : world_indices) worlds.push_back(&l.world(w));
    const uint32_t step = static_cast<uint32_t>(std::min<int64_t>(stride, std::numeric_limits<uint32_t>::max()));
    const uint32_t points = gathered_point_count(worlds, step);
    py::array_t<float> out({static_cast<py::ssize_t>(worlds.size()), static_cast<py::ssize_t>(rows.size()),
                            static_cast<py::ssize_t>(points), py::ssize_t{3}});
    float* data = out.mutable_data();
    {
        py::gil_scoped_release release;
        gather_polylines(worlds, rows, step, points, data);
    }
    return out;
}

// One refinement of a world's lineage, as Python sees it.
struct LineageStepInfo {
    double branch_time_s = 0;
    uint64_t world = 0;  ///< the world this step made
    std::vector<uint32_t> bodies, added, removed;
};

// Where a world came from and what it holds.
struct WorldInfo {
    uint64_t seed = 0;
    int64_t parent_world = -1;
    double branch_time_s = 0;
    double record_hz = 0;
    uint32_t first_frame = 0, frame_count = 0;
    double simulated_time_s = 0;
    uint32_t impacts_perturbed = 0;
    size_t checkpoint_count = 0;
    uint64_t root_world = 0;
    std::vector<LineageStepInfo> lineage;
    std::vector<bool> changed_bodies;
    size_t motion_bytes = 0;
};

WorldInfo world_info(const PyLibrary& l, uint64_t w) {
    const StoredWorld& world = l.world(w);
    WorldInfo info;
    info.seed = world.seed;
    info.parent_world = world.parent_world;
    info.branch_time_s = world.branch_time_s;
    info.record_hz = world.record_hz;
    info.first_frame = world.first_frame;
    info.frame_count = world.frame_count;
    info.simulated_time_s = world.simulated_time_s;
    info.impacts_perturbed = world.impacts_perturbed;
    info.checkpoint_count = checkpoint_count(world.checkpoints);
    info.root_world = world.lineage.empty() ? world.world_index : world.root_world;
    for (const RefineStep& step : world.lineage)
        info.lineage.push_back({static_cast<double>(step.branch_step) / world.step_hz, step.world_index, step.bodies,
                                step.added, step.removed});
    info.changed_bodies = per_body<bool>(l, world, false, [&](const StoredTrack& t, size_t) {
        return world.parent_world >= 0 && !t.inherited;
    });
    for (const StoredTrack& t : world.tracks) info.motion_bytes += t.position.size() + t.rotation.size();
    return info;
}

void bind_world_info(py::module_& m) {
    py::class_<LineageStepInfo>(m, "LineageStep", "One refinement in a world's lineage.")
        .def_readonly("branch_time_s", &LineageStepInfo::branch_time_s, "where the world left its parent, seconds")
        .def_readonly("world", &LineageStepInfo::world, "the world this step made")
        .def_readonly("bodies", &LineageStepInfo::bodies, "scene body indices simulated anew")
        .def_readonly("added", &LineageStepInfo::added, "scene body indices added from t = 0")
        .def_readonly("removed", &LineageStepInfo::removed, "scene body indices removed from t = 0");
    py::class_<WorldInfo>(m, "WorldInfo", "Where a world came from and what it holds.")
        .def_readonly("seed", &WorldInfo::seed)
        .def_readonly("parent_world", &WorldInfo::parent_world, "-1 for a sampled world")
        .def_readonly("branch_time_s", &WorldInfo::branch_time_s)
        .def_readonly("record_hz", &WorldInfo::record_hz)
        .def_readonly("first_frame", &WorldInfo::first_frame)
        .def_readonly("frame_count", &WorldInfo::frame_count)
        .def_readonly("simulated_time_s", &WorldInfo::simulated_time_s)
        .def_readonly("impacts_perturbed", &WorldInfo::impacts_perturbed)
        .def_readonly("checkpoint_count", &WorldInfo::checkpoint_count)
        .def_readonly("root_world", &WorldInfo::root_world, "the sampled world its lineage starts from")
        .def_readonly("lineage", &WorldInfo::lineage, "list of LineageStep, the root's first refinement first")
        .def_readonly("changed_bodies", &WorldInfo::changed_bodies, "per body: simulated anew (refined worlds)")
        .def_readonly("motion_bytes", &WorldInfo::motion_bytes, "compressed motion the world stores itself");
}

}  // namespace

void bind_library(py::module_& m) {
    bind_world_info(m);
    py::register_exception<LibraryError>(m, "LibraryError", PyExc_IOError);
    py::register_exception<CodecError>(m, "CodecError", PyExc_ValueError);

    py::class_<RunHeader>(m, "LibraryHeader", "The run a library holds, as sampled (library/RunHeader.h).")
        .def_readonly("scene_json", &RunHeader::scene_json, "the scene the worlds were sampled in")
        .def_readonly("base_seed", &RunHeader::base_seed)
        .def_property_readonly("position_error_max_m", [](const RunHeader& h) { return h.bounds.position_error_max_m; })
        .def_property_readonly("rotation_error_max_rad", [](const RunHeader& h) { return h.bounds.rotation_error_max_rad; })
        .def_property_readonly("scene_hash", [](const RunHeader& h) { return scene_hash(h); })
        .def_property_readonly("run_hash", [](const RunHeader& h) { return run_hash(h); })
        .def_readonly("engine_build", &RunHeader::engine_build, "empty in libraries made before builds were recorded")
        .def_readonly("parameters", &RunHeader::parameters);

    py::class_<WorldMetrics>(m, "WorldMetrics", "A world's stored metrics: per name, one value per scene body.")
        .def_readonly("names", &WorldMetrics::names, "in stored order")
        .def("__getitem__", &WorldMetrics::of, py::arg("name"), "per-body values of one metric (KeyError: no such metric)")
        .def("__contains__", [](const WorldMetrics& w, const std::string& name) { return w.values.count(name) > 0; })
        .def("get", [](const WorldMetrics& w, const std::string& name, std::vector<double> otherwise) {
            const auto it = w.values.find(name);
            return it == w.values.end() ? otherwise : it->second;
        }, py::arg("name"), py::arg("otherwise") = std::vector<double>{});

    py::class_<PyLibrary>(m, "Library", "A .mwb library file: run header, worlds (compressed in memory), rejections.")
        .def(py::init<const std::string&, double>(), py::arg("path"), py::arg("polyline_hz") = 30.0,
             py::call_guard<py::gil_scoped_release>(),
             "Open a library; every world is decoded once on load to derive its polyline at polyline_hz.")
        .def_property_readonly("path", [](const PyLibrary& l) { return l.reader().path(); })
        .def_property_readonly("header", [](const PyLibrary& l) { return l.reader().header(); },
                               "the run as sampled (LibraryHeader); its scene_json is the scene the worlds were sampled in")
        .def_property_readonly("scene_json", [](const PyLibrary& l) { return l.reader().scene_json(); },
                               "the library's scene now: the sampled scene plus bodies added to worlds since, "
                               "appended (a body's index never changes); grows on poll()")
        .def_property_readonly("next_world_index", [](const PyLibrary& l) { return l.reader().next_world_index(); },
                               "first world index after every world, stored or rejected: where new worlds go")
        .def_property_readonly("run_last_frame", [](const PyLibrary& l) { return l.reader().run_last_frame(); },
                               "the run's last recorded frame: a world that ended earlier (every body at rest) holds\n"
                               "its final pose up to this frame; no world has a pose beyond it")
        .def_property_readonly("body_count", [](const PyLibrary& l) { return l.reader().scene_body_count(); },
                               "bodies in scene_json; every per-body array has this many rows")
        .def("present",
             [](const PyLibrary& l, uint64_t w) {
                 return per_body<bool>(l, l.world(w), false, [](const StoredTrack&, size_t) { return true; });
             },
             py::arg("world"), "list of bool, per body: whether the world has it (bodies can be added and removed)")
        .def_property_readonly("warnings", [](const PyLibrary& l) { return l.reader().warnings(); })
        .def_property_readonly("file_bytes", [](const PyLibrary& l) { return l.reader().file_size(); })
        .def_property_readonly("world_indices",
                               [](const PyLibrary& l) {
                                   std::vector<uint64_t> ids;
                                   for (const StoredWorld& w : l.reader().worlds()) ids.push_back(w.world_index);
                                   return ids;
                               },
                               "world indices in file order")
        .def_property_readonly("rejections",
                               [](const PyLibrary& l) {
                                   py::list out;
                                   for (const StoredRejection& r : l.reader().rejections())
                                       out.append(py::make_tuple(r.world_index, r.seed, r.reason));
                                   return out;
                               },
                               "list of (world_index, seed, reason)")
        .def("poll", &PyLibrary::poll, "Read worlds appended since the last read; returns how many arrived.")
        .def("frame_count", [](const PyLibrary& l, uint64_t w) { return l.world(w).frame_count; }, py::arg("world"))
        .def("positions",
             [](const PyLibrary& l, uint64_t w) { return decoded(l, w, decode_world_positions, 3); },
             py::arg("world"), "float64 (bodies, frames, 3): decoded object origins, metres; NaN for absent bodies")
        .def("orientations",
             [](const PyLibrary& l, uint64_t w) { return decoded(l, w, decode_world_orientations, 4); },
             py::arg("world"), "float64 (bodies, frames, 4): decoded unit quaternions (w, x, y, z); NaN for absent bodies")
        .def("poses", &world_poses, py::arg("world"), py::arg("frames"), py::arg("bodies") = py::none(),
             "Poses of `bodies` (scene body indices; None: all) at fractional recorded frames (clamped to the\n"
             "world's), as bake keys them and a preview shows them: (loc float64 (bodies, n, 3), rot float64\n"
             "(bodies, n, 4)), quaternions sign-continuous; NaN for bodies the world lacks. The last world\n"
             "asked stays decoded for the next call.")
        .def("pose",
             [](const PyLibrary& l, uint64_t w, size_t body, uint32_t frame) {
                 const Transform t = decode_pose(l.world(w), body, frame);
                 return py::make_tuple(t.location, t.rotation);
             },
             py::arg("world"), py::arg("body"), py::arg("frame"),
             "(location, quaternion) of one body at one frame, decoding only that body's track")
        .def("polyline",
             [](const PyLibrary& l, uint64_t w) {
                 const StoredWorld& world = l.world(w);
                 const size_t bodies = body_rows(l, world);
                 py::array_t<float> out({static_cast<py::ssize_t>(bodies), static_cast<py::ssize_t>(world.polyline_points),
                                         py::ssize_t{3}});
                 std::vector<uint32_t> all(bodies);
                 for (uint32_t b = 0; b < bodies; ++b) all[b] = b;
                 gather_polylines({&world}, all, 1, world.polyline_points, out.mutable_data());
                 return out;
             },
             py::arg("world"),
             "float32 (bodies, points, 3): the path down-sampled on load (every polyline_stride-th frame and the\n"
             "last); NaN for absent bodies")
        .def("polylines", &gathered_polylines, py::arg("worlds"), py::arg("bodies"), py::arg("stride") = 1,
             "float32 (len(worlds), len(bodies), points, 3): the given bodies' polylines of many worlds at once,\n"
             "each thinned to its points 0, stride, 2 stride, ... and its last, as polyline(world)[bodies] would\n"
             "be; NaN for bodies a world does not have and after a path shorter than the longest. KeyError for a\n"
             "world not in the library, IndexError for a body out of range, ValueError for stride < 1.")
        .def("polyline_stride", [](const PyLibrary& l, uint64_t w) { return l.world(w).polyline_stride; }, py::arg("world"))
        .def("rest_times",
             [](const PyLibrary& l, uint64_t w) {
                 return per_body<double>(l, l.world(w), 0.0, [](const StoredTrack& t, size_t) { return t.rest_time_s; });
             },
             py::arg("world"), "per body: start of its final rest, seconds (0 for absent bodies)")
        .def("contacts",
             [](const PyLibrary& l, uint64_t w) {
                 py::list out;
                 for (const ContactEvent& e : l.world(w).contacts) out.append(py::make_tuple(e.time_s, e.body, e.other, e.impulse_ns));
                 return out;
             },
             py::arg("world"), "list of (time_s, body, other, impulse_ns)")
        .def("metrics",
             [](const PyLibrary& l, uint64_t w) {
                 WorldMetrics out;
                 const StoredWorld& world = l.world(w);
                 for (const MetricValues& m : world.metrics) {
                     out.names.push_back(m.name);
                     out.values[m.name] =
                         per_body<double>(l, world, 0.0, [&](const StoredTrack&, size_t t) { return m.per_body[t]; });
                 }
                 return out;
             },
             py::arg("world"), "The world's stored metrics (WorldMetrics): per name, per-body values (0 for absent bodies)")
        .def("world_info", &world_info, py::arg("world"), "Where a world came from and what it holds (WorldInfo).");

    m.def(
        "thinned_indices",
        [](int64_t points, int64_t stride) {
            if (stride < 1) throw py::value_error("stride must be at least 1, got " + std::to_string(stride));
            if (points < 0 || points > std::numeric_limits<uint32_t>::max())
                throw py::value_error("points out of range: " + std::to_string(points));
            const auto step = static_cast<uint32_t>(std::min<int64_t>(stride, std::numeric_limits<uint32_t>::max()));
            const std::vector<uint32_t> kept = kept_point_indices(static_cast<uint32_t>(points), step);
            py::array_t<py::ssize_t> out(static_cast<py::ssize_t>(kept.size()));
            std::copy(kept.begin(), kept.end(), out.mutable_data());
            return out;
        },
        py::arg("points"), py::arg("stride"),
        "Indices of the points a path of `points` points keeps at `stride`: 0, stride, 2 stride, ... and the last\n"
        "(as Library.polylines gathers them).");
    m.def("merge_libraries", &merge_libraries, py::arg("inputs"), py::arg("output"),
          py::call_guard<py::gil_scoped_release>(),
          "Merge libraries of one run into a new file; returns warnings. Raises LibraryError on mismatch or collisions.");
}

}  // namespace mwb::python
