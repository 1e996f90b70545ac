#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "PyLibrary.h"
#include "geometry/ShapeBounds.h"
#include "library/WorldDecoding.h"
#include "query/PathIndex.h"
#include "query/RankingMetrics.h"
#include "query/ScreenBox.h"
#include "scene/SceneJson.h"
#include "seek/WorldIndexing.h"

namespace py = pybind11;

namespace mwb::python {
namespace {

Matrix4 to_matrix(const py::array_t<double, py::array::c_style | py::array::forcecast>& m, const char* name) {
    if (m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4)
        throw py::value_error(std::string(name) + " must be a (4, 4) matrix, got " + std::to_string(m.ndim()) +
                              " dimensions and " + std::to_string(m.size()) + " values");
    Matrix4 out;
    std::copy(m.data(), m.data() + 16, out.begin());
    return out;
}

QueryBox make_box(const py::array_t<double, py::array::c_style | py::array::forcecast>& view,
                  const py::array_t<double, py::array::c_style | py::array::forcecast>& projection,
                  std::pair<double, double> viewport, std::array<double, 4> rect, bool negative,
                  std::vector<uint32_t> bodies, std::optional<std::pair<double, double>> time_window, bool swept,
                  int32_t after) {
    ScreenBoxSpec spec;
    spec.view = to_matrix(view, "view");
    spec.projection = to_matrix(projection, "projection");
    spec.viewport_width = viewport.first;
    spec.viewport_height = viewport.second;
    spec.rect = rect;
    spec.negative = negative;
    spec.swept = swept;
    spec.bodies = std::move(bodies);
    spec.time_window = time_window;
    spec.after = after;
    try {
        return make_query_box(spec);
    } catch (const std::invalid_argument& error) {
        throw py::value_error(error.what());
    }
}

// What the index needs of the library's worlds it does not hold yet: at most `limit` (0: all), in
// file order. Runs without the GIL, under the library's read lock.
std::vector<IndexedWorldInput> new_worlds(const PathIndex& index, const PyLibrary& library, size_t limit) {
    const auto lock = library.read_lock();
    std::vector<IndexedWorldInput> inputs;
    for (const StoredWorld& w : library.reader().worlds()) {
        if (limit != 0 && inputs.size() == limit) break;
        if (!index.contains(w.world_index)) inputs.push_back(indexed_world_input(library.reader(), w));
    }
    return inputs;
}

}  // namespace

void bind_query(py::module_& m) {
    py::class_<QueryBox>(m, "QueryBox", "A screen rectangle seen through a camera: a frustum in world space.")
        .def(py::init(&make_box), py::arg("view"), py::arg("projection"), py::arg("viewport"), py::arg("rect"),
             py::arg("negative") = false, py::arg("bodies"), py::arg("time_window") = py::none(),
             py::arg("swept") = false, py::arg("after") = -1,
             "view: (4, 4) world-to-camera; projection: (4, 4) camera-to-clip (OpenGL); viewport: (width, height)\n"
             "pixels; rect: (x0, y0, x1, y1) pixels from the bottom-left; bodies: scene body indices;\n"
             "time_window: (start_s, end_s) or None; swept: test bounding spheres, not only origins;\n"
             "after: position, in the list of boxes queried together, of the box this one must be met after.")
        .def_readonly("negative", &QueryBox::negative)
        .def_readonly("bodies", &QueryBox::bodies)
        .def_readonly("swept", &QueryBox::swept)
        .def_readonly("after", &QueryBox::after);

    py::class_<PathIndex>(m, "PathIndex", "Body paths of many worlds in OBB trees, for box queries and rankings.")
        .def(py::init<std::vector<double>>(), py::arg("body_radii_m"),
             "body_radii_m: per scene body, a radius around the object origin bounding its shape")
        .def(
            "add_library",
            [](PathIndex& index, const PyLibrary& library, int threads, size_t limit) {
                py::gil_scoped_release release;
                std::vector<IndexedWorldInput> inputs;
                try {
                    inputs = new_worlds(index, library, limit);
                } catch (const std::invalid_argument& error) {
                    throw py::value_error(error.what());
                }
                const size_t count = inputs.size();
                index.add_worlds(std::move(inputs), threads);
                return count;
            },
            py::arg("library"), py::arg("threads") = 0, py::arg("limit") = 0,
            py::keep_alive<1, 2>(),  // the index reads the library's polylines, which it does not copy
            "Index the library's worlds not indexed yet, at most `limit` of them (0: all) in file order, on\n"
            "`threads` threads (0: all); returns how many. Runs without the GIL, so a Python thread can fill\n"
            "the index while queries (which see the worlds indexed so far) and library polls go on.")
        .def_property_readonly("world_count", &PathIndex::world_count)
        .def_property_readonly("memory_bytes", &PathIndex::memory_bytes)
        .def(
            "query",
            [](const PathIndex& index, const std::vector<QueryBox>& boxes, uint64_t generation, bool brute_force) {
                QueryResult result;
                try {
                    py::gil_scoped_release release;
                    result = index.query(boxes, generation, brute_force);
                } catch (const std::invalid_argument& error) {
                    throw py::value_error(error.what());
                }
                py::dict d;
                d["superseded"] = result.superseded;
                d["world_indices"] = py::array_t<uint64_t>(result.world_indices.size(), result.world_indices.data());
                d["boxes_satisfied"] = py::array_t<uint32_t>(result.boxes_satisfied.size(), result.boxes_satisfied.data());
                d["matching"] = py::array_t<uint64_t>(result.matching.size(), result.matching.data());
                return d;
            },
            py::arg("boxes"), py::arg("generation") = 0, py::arg("brute_force") = false,
            "Evaluate boxes (AND; ordered boxes in their order). Returns world_indices, boxes_satisfied (per world), matching, superseded.\n"
            "Runs with the GIL released; a later post_generation(g) with g > generation stops it early.")
        .def("post_generation", &PathIndex::post_generation, py::arg("generation"))
        .def(
            "rank",
            [](const PathIndex& index, const std::string& metric, const std::vector<uint32_t>& bodies,
               const std::string& combine, bool descending, std::optional<std::vector<uint64_t>> only,
               std::optional<std::vector<std::array<double, 4>>> goals, std::optional<std::vector<QueryBox>> boxes) {
                if (combine != "sum" && combine != "max") throw py::value_error("combine must be 'sum' or 'max'");
                if (only) std::sort(only->begin(), only->end());
                std::vector<Quat> goal_quats;
                if (goals)
                    for (const auto& g : *goals) goal_quats.push_back(quat_normalized(g));
                std::vector<std::pair<uint64_t, double>> ranked;
                try {
                    py::gil_scoped_release release;
                    ranked = index.rank(metric, bodies, combine == "sum" ? Combine::Sum : Combine::Max, descending,
                                        only ? &*only : nullptr, goals ? &goal_quats : nullptr, boxes ? &*boxes : nullptr);
                } catch (const std::invalid_argument& error) {
                    throw py::value_error(error.what());
                }
                py::array_t<uint64_t> ids(ranked.size());
                py::array_t<double> values(ranked.size());
                for (size_t k = 0; k < ranked.size(); ++k) {
                    ids.mutable_at(k) = ranked[k].first;
                    values.mutable_at(k) = ranked[k].second;
                }
                return py::make_tuple(ids, values);
            },
            py::arg("metric"), py::arg("bodies"), py::arg("combine") = "sum", py::arg("descending") = false,
            py::arg("only") = py::none(), py::arg("goals") = py::none(), py::arg("boxes") = py::none(),
            "Worlds sorted by a metric over bodies: (world ids uint64, values float64). boxes_met needs `boxes`.")
        .def(
            "score",
            [](const PathIndex& index, uint64_t world, const std::vector<QueryBox>& boxes) {
                GoalScore score;
                try {
                    score = index.score(world, boxes, goal_order(boxes));
                } catch (const std::invalid_argument& error) {
                    throw py::value_error(error.what());
                }
                py::dict d;
                d["boxes_met"] = score.boxes_met;
                d["met"] = std::vector<bool>(score.met.begin(), score.met.end());
                d["met_time_s"] = score.met_time_s;
                d["first_unmet"] = score.first_unmet;
                d["closeness"] = score.closeness;
                d["value"] = score.value();
                d["failure_time_s"] = score.failure_time_s;
                d["failing_bodies"] = score.failing_bodies;
                return d;
            },
            py::arg("world"), py::arg("boxes"),
            "How far a world gets towards the goal `boxes`: boxes_met (along the order), met, met_time_s,\n"
            "first_unmet (-1: all met), closeness to it in [0, 1), value = boxes_met + closeness,\n"
            "failure_time_s and failing_bodies (where and who missed it).")
        .def(
            "first_time_inside",
            [](const PathIndex& index, uint64_t world, const std::vector<uint32_t>& bodies, const QueryBox& box) {
                return index.first_time_inside(world, bodies, box.frustum);
            },
            py::arg("world"), py::arg("bodies"), py::arg("box"),
            "First time (s) any of the bodies' paths is inside the box's frustum, or -1.");

    py::class_<RankingMetric>(m, "RankingMetric", "A metric worlds can be ranked by.")
        .def_readonly("name", &RankingMetric::name)
        .def_readonly("label", &RankingMetric::label)
        .def_readonly("unit", &RankingMetric::unit, "'rad', 's', 'm', 'hits' or 'boxes'")
        .def_readonly("help", &RankingMetric::help)
        .def("__repr__", [](const RankingMetric& r) { return "<RankingMetric " + r.name + " (" + r.unit + ")>"; });
    m.def("ranking_metrics", &ranking_metrics, py::return_value_policy::copy,
          "Every metric worlds can be ranked by: the stored per-body ones, then orientation_to_goal_rad and boxes_met.");

    m.def(
        "check_goal",
        [](const std::vector<QueryBox>& boxes) {
            try {
                check_goal(boxes);
            } catch (const std::invalid_argument& error) {
                throw py::value_error(error.what());
            }
        },
        py::arg("boxes"),
        "Raise ValueError unless the boxes make a goal: at least one, each `after` another box of the list, no cycle.");

    m.def(
        "body_bounding_radii",
        [](const Scene& scene) {
            std::vector<double> radii;
            for (const Body& b : scene.bodies) radii.push_back(body_bounding_radius(b));
            return radii;
        },
        py::arg("scene"), "Per body: radius around the object origin that bounds its collision shape (metres).");
}

}  // namespace mwb::python
