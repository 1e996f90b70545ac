#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "PyLibrary.h"
#include "geometry/ShapeBounds.h"
#include "library/WorldDecoding.h"
#include "query/GoalScore.h"
#include "query/PathIndex.h"
#include "query/RankingMetrics.h"
#include "query/ScreenBox.h"
#include "scene/SceneJson.h"
#include "seek/GoalJson.h"
#include "seek/GoalSearch.h"
#include "seek/WorldIndexing.h"

namespace py = pybind11;

namespace mwb::python {
namespace {

// A ranking as Python sees it: two arrays of one length.
struct Ranking {
    std::vector<uint64_t> world_indices;
    std::vector<double> values;
};

template <typename T>
py::array_t<T> as_numpy(const std::vector<T>& values) {
    return py::array_t<T>(static_cast<py::ssize_t>(values.size()), values.data());
}

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

QueryBox make_pose_part(std::vector<uint32_t> bodies, double within_deg, std::array<double, 3> axis,
                        std::array<double, 3> target, bool negative, double longer_than_s,
                        std::optional<std::pair<double, double>> time_window, int32_t after) {
    OrientationPartSpec spec;
    spec.bodies = std::move(bodies);
    spec.within_deg = within_deg;
    spec.axis = {axis[0], axis[1], axis[2]};
    spec.target = {target[0], target[1], target[2]};
    spec.negative = negative;
    spec.longer_than_s = longer_than_s;
    spec.time_window = time_window;
    spec.after = after;
    try {
        return make_orientation_part(spec);
    } catch (const std::invalid_argument& error) {
        throw py::value_error(error.what());
    }
}

// An open library's rotations for the index's pose parts, decoded when a query asks for them.
// The index keeps the library alive (add_library's keep_alive).
class LibraryRotations : public RotationSource {
public:
    explicit LibraryRotations(const PyLibrary& library) : library_(library) {}
    BodyOrientations rotations_at_path_points(uint64_t world_index, const std::vector<uint32_t>& bodies) const override {
        const auto lock = library_.read_lock();
        const StoredWorld* world = library_.find(world_index);
        if (!world) throw std::invalid_argument("world " + std::to_string(world_index) + " is not in the library");
        return mwb::rotations_at_path_points(*world, bodies);
    }

private:
    const PyLibrary& library_;
};

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
        .def_readonly("after", &QueryBox::after)
        .def_property_readonly("is_pose", [](const QueryBox& b) { return b.orientation.has_value(); },
                               "whether this is a pose part (pose_part), not a screen box");
    m.def("pose_part", &make_pose_part, py::arg("bodies"), py::arg("within_deg"), py::arg("axis") = std::array<double, 3>{0, 0, 1},
          py::arg("target") = std::array<double, 3>{0, 0, 1}, py::arg("negative") = false, py::arg("longer_than_s") = 0.0,
          py::arg("time_window") = py::none(), py::arg("after") = -1,
          "A pose part of a goal, queried with boxes: each body's own `axis` (body frame) within `within_deg`\n"
          "degrees of the world direction `target`, at every moment of time_window (s; None: the whole path).\n"
          "negative: no body stays so for longer than longer_than_s instead. after: as for QueryBox.\n"
          "An index answers it once filled with add_library (it reads the library's rotations).");

    py::class_<QueryResult>(m, "QueryResult", "What a query of boxes found, over every indexed world.")
        .def_property_readonly("world_indices", [](const QueryResult& r) { return as_numpy(r.world_indices); },
                               "uint64: every indexed world, in world-index order")
        .def_property_readonly("boxes_satisfied", [](const QueryResult& r) { return as_numpy(r.boxes_satisfied); },
                               "uint32, per world of world_indices: the boxes it meets")
        .def_property_readonly("matching", [](const QueryResult& r) { return as_numpy(r.matching); },
                               "uint64: the worlds meeting every box")
        .def_readonly("superseded", &QueryResult::superseded, "a newer query was posted; the rest is incomplete");

    py::class_<Ranking>(m, "Ranking", "Worlds sorted by a metric.")
        .def_property_readonly("world_indices", [](const Ranking& r) { return as_numpy(r.world_indices); }, "uint64")
        .def_property_readonly("values", [](const Ranking& r) { return as_numpy(r.values); },
                               "float64, per world of world_indices");

    py::class_<GoalScore>(m, "GoalScore", "How far a world gets towards a goal (query/GoalScore.h).")
        .def_readonly("boxes_met", &GoalScore::boxes_met, "along the goal's order")
        .def_property_readonly("met", [](const GoalScore& g) { return std::vector<bool>(g.met.begin(), g.met.end()); },
                               "per box")
        .def_readonly("met_time_s", &GoalScore::met_time_s)
        .def_readonly("first_unmet", &GoalScore::first_unmet, "-1: every box is met")
        .def_readonly("closeness", &GoalScore::closeness,
                      "to the first unmet box, in [0, 1); for a world that broke a negative part, how late it broke")
        .def_readonly("violation_time_s", &GoalScore::violation_time_s,
                      "when it first entered a negative part it misses; inf if none")
        .def_readonly("parts_before_violation", &GoalScore::parts_before_violation,
                      "parts met before that moment, poses waiting on a missed box left out (boxes_met when neither)")
        .def_property_readonly("value", &GoalScore::value, "parts_before_violation + closeness: what a search ranks by")
        .def_readonly("failure_time_s", &GoalScore::failure_time_s)
        .def_readonly("failing_bodies", &GoalScore::failing_bodies);

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
                index.set_rotation_source(std::make_shared<LibraryRotations>(library));
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
                return result;
            },
            py::arg("boxes"), py::arg("generation") = 0, py::arg("brute_force") = false,
            "Evaluate boxes (AND; ordered boxes in their order): a QueryResult.\n"
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
                Ranking ranking;
                for (const auto& [world, value] : ranked) {
                    ranking.world_indices.push_back(world);
                    ranking.values.push_back(value);
                }
                return ranking;
            },
            py::arg("metric"), py::arg("bodies"), py::arg("combine") = "sum", py::arg("descending") = false,
            py::arg("only") = py::none(), py::arg("goals") = py::none(), py::arg("boxes") = py::none(),
            "Worlds sorted by a metric over bodies: a Ranking. boxes_met needs `boxes`.")
        .def(
            "score",
            [](const PathIndex& index, uint64_t world, const std::vector<QueryBox>& boxes) {
                try {
                    return index.score(world, boxes, goal_order(boxes));
                } catch (const std::invalid_argument& error) {
                    throw py::value_error(error.what());
                }
            },
            py::arg("world"), py::arg("boxes"), "How far a world gets towards the goal `boxes`: a GoalScore.")
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

    py::register_exception<GoalError>(m, "GoalError", PyExc_ValueError);
    m.def(
        "worlds_meeting_goal",
        [](const std::string& library_path, const std::string& goal_json, int threads) {
            py::gil_scoped_release release;
            return worlds_meeting_goal(library_path, goal_json, threads);
        },
        py::arg("library_path"), py::arg("goal_json"), py::arg("threads") = 0,
        "The worlds of the library meeting a goal file's text (boxes and orientation parts), as the "
        "goal search scores them; ascending. Raises ValueError for a goal that does not fit the library.");
    m.def(
        "goal_order",
        [](const std::vector<int32_t>& afters) {
            try {
                return goal_order(afters);
            } catch (const std::invalid_argument& error) {
                throw py::value_error(error.what());
            }
        },
        py::arg("afters"),
        "The order parts are met in, given each part's `after` (-1: none); ValueError for a part after\n"
        "itself or a missing part, or a cycle (query/GoalScore.h).");
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
