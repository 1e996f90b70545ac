// Query benchmarks over synthetic paths shaped like sampled ones: bodies thrown, bouncing on
// the ground and coming to rest, 1,500 worlds × 200 bodies × 10 s at 30 Hz (or the worlds and
// bodies given). A pose part reads rotation tracks compressed by the library's own codec.
#include <chrono>
#include <cstdlib>
#include <memory>
#include <unordered_map>
#include <vector>

#include "BenchReport.h"
#include "codec/CodecFormat.h"
#include "codec/RotationEncoder.h"
#include "common/QuantizedPolyline.h"
#include "library/WorldDecoding.h"
#include "query/PathIndex.h"
#include "query/ScreenBox.h"
#include "sim/PortableRandom.h"

namespace mwb::bench {
namespace {

constexpr int kPointsPerPath = 301;  // 10 s at 30 Hz

std::vector<float> bouncing_path(PortableRandom& random) {
    Vec3 p{random.uniform(-4, 4), random.uniform(-4, 4), random.uniform(1, 6)};
    Vec3 v{random.uniform(-2, 2), random.uniform(-2, 2), random.uniform(-1, 4)};
    const double dt = 1.0 / 30;
    std::vector<float> points;
    points.reserve(kPointsPerPath * 3);
    for (int k = 0; k < kPointsPerPath; ++k) {
        points.insert(points.end(), {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
        v[2] -= 9.81 * dt;
        p = add(p, scale(v, dt));
        if (p[2] < 0.2) {  // bounce with losses, then roll to a stop
            p[2] = 0.2;
            v = {v[0] * 0.7, v[1] * 0.7, std::fabs(v[2]) * 0.5};
            if (v[2] < 0.3) v[2] = 0;
        }
    }
    return points;
}

constexpr uint32_t kFrames = (kPointsPerPath - 1) * 4 + 1;  // 120 Hz

// A body tumbling about a random axis, slowing to rest by 3 s: (kFrames, 4) w, x, y, z.
std::vector<double> tumbling_track(PortableRandom& random) {
    Vec3 axis{random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1)};
    axis = scale(axis, 1 / std::max(1e-9, norm(axis)));
    const double spin = random.uniform(2, 12);  // rad/s at the start
    std::vector<double> wxyz;
    wxyz.reserve(size_t{kFrames} * 4);
    for (uint32_t f = 0; f < kFrames; ++f) {
        const double t = std::min(3.0, f / 120.0);
        const Quat q = quat_from_axis_angle(axis, spin * (t - t * t / 6));
        wxyz.insert(wxyz.end(), {q[0], q[1], q[2], q[3]});
    }
    return wxyz;
}

// Worlds as the library holds them, for the posed bodies only (the others' tracks are never read).
class CompressedRotations : public RotationSource {
public:
    void add(uint64_t world, StoredWorld stored) { worlds_.emplace(world, std::move(stored)); }
    BodyOrientations rotations_at_path_points(uint64_t world, const std::vector<uint32_t>& bodies) const override {
        return mwb::rotations_at_path_points(worlds_.at(world), bodies);
    }

private:
    std::unordered_map<uint64_t, StoredWorld> worlds_;
};

Matrix4 perspective(double fov_y, double aspect, double n, double f) {
    const double c = 1 / std::tan(fov_y / 2);
    return {c / aspect, 0, 0, 0, 0, c, 0, 0, 0, 0, -(f + n) / (f - n), -2 * f * n / (f - n), 0, 0, -1, 0};
}

}  // namespace
}  // namespace mwb::bench

int main(int argc, char** argv) {
    using namespace mwb;
    using namespace mwb::bench;
    const int worlds = argc > 1 ? std::atoi(argv[1]) : 1500;
    const int bodies = argc > 2 ? std::atoi(argv[2]) : 200;
    std::printf("Path index: %d worlds x %d bodies x 10 s, 30 Hz polylines (synthetic bouncing paths)\n", worlds, bodies);
    // The paths live outside the index, as the library's polylines do in the add-on (one buffer
    // per world, drawn from the same memory); the index borrows them and keeps only its boxes.
    std::vector<std::vector<uint16_t>> world_points(static_cast<size_t>(worlds));
    std::vector<IndexedWorldInput> inputs(static_cast<size_t>(worlds));
    PortableRandom random(5);
    size_t path_bytes = 0;
    for (int w = 0; w < worlds; ++w) {
        IndexedWorldInput& in = inputs[static_cast<size_t>(w)];
        in.world_index = static_cast<uint64_t>(w);
        in.last_frame = (kPointsPerPath - 1) * 4;
        // Quantized to 16 bits per coordinate, as the library keeps them.
        const size_t words = quantized::block_words(kPointsPerPath);
        std::vector<uint16_t>& points = world_points[static_cast<size_t>(w)];
        points.resize(words * static_cast<size_t>(bodies));
        for (int b = 0; b < bodies; ++b) {
            const std::vector<float> path = bouncing_path(random);
            quantized::encode(kPointsPerPath, [&](uint32_t k, int a) { return path[3 * size_t{k} + a]; },
                              points.data() + words * static_cast<size_t>(b));
            in.final_orientations.push_back({1, 0, 0, 0});
        }
        for (int b = 0; b < bodies; ++b)
            in.borrowed.push_back({points.data() + words * static_cast<size_t>(b), kPointsPerPath});
        path_bytes += points.size() * sizeof(uint16_t);
    }
    PathIndex index(std::vector<double>(static_cast<size_t>(bodies), 0.2));
    auto start = std::chrono::steady_clock::now();
    index.add_worlds(std::move(inputs), 0);
    const std::string size = std::to_string(worlds) + "x" + std::to_string(bodies);
    report("index_build_s_" + size, seconds_since(start), "s", "all cores");
    report("index_memory_mb_" + size, static_cast<double>(index.memory_bytes()) / (1 << 20), "MB",
           "boxes, roots and metrics; the points are the library's");
    report("path_points_mb_" + size, static_cast<double>(path_bytes) / (1 << 20), "MB",
           "the 16-bit polylines the index reads, held by the library for drawing");

    // The camera looks down at the scene from 12 m; boxes of a fifth of the screen.
    const Matrix4 view{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -12, 0, 0, 0, 1};
    std::vector<uint32_t> all(static_cast<size_t>(bodies));
    for (int b = 0; b < bodies; ++b) all[static_cast<size_t>(b)] = static_cast<uint32_t>(b);
    QueryBox keep, reject;
    keep.frustum = make_screen_frustum(view, perspective(1.0, 1.6, 0.1, 100), 1600, 1000, 700, 400, 1000, 600);
    keep.bodies = {0, 1, 2};
    reject.frustum = make_screen_frustum(view, perspective(1.0, 1.6, 0.1, 100), 1600, 1000, 100, 100, 400, 300);
    reject.negative = true;
    reject.bodies = all;
    const std::vector<QueryBox> boxes{keep, reject};
    auto time_query = [&](bool brute, int threads = 1) {
        double best = 1e9;
        size_t matches = 0;
        for (int repeat = 0; repeat < 5; ++repeat) {
            start = std::chrono::steady_clock::now();
            matches = index.query(boxes, 0, brute, threads).matching.size();
            best = std::min(best, seconds_since(start));
        }
        return std::make_pair(best, matches);
    };
    const auto [tree_s, tree_matches] = time_query(false);
    const auto [brute_s, brute_matches] = time_query(true);
    const auto [tree2_s, tree2_matches] = time_query(false, 2);
    if (tree_matches != brute_matches) {
        std::printf("tree and brute force disagree: %zu vs %zu\n", tree_matches, brute_matches);
        return 1;
    }
    report("query_ms_" + size, tree_s * 1000, "ms",
           "1 thread; positive box on 3 bodies + negative box on all (target < 16 ms); " +
               std::to_string(tree_matches) + " matches");
    report("obb_speedup", brute_s / tree_s, "x", "brute force / tree, same query (target >= 5)");
    report("query_ms_" + size + "_2t", tree2_s * 1000, "ms",
           "2 threads, same query; " + std::to_string(tree2_matches) + " matches");
    report("query_speedup_2t", tree_s / tree2_s, "x", "1 thread / 2 threads, same query");

    // A pose part (a die ends upright in the last second) on one body, beside the two boxes: the
    // time the match count takes once it is added, and a box dragged while it stays enabled.
    auto rotations = std::make_shared<CompressedRotations>();
    const uint32_t posed_body = 0;
    for (int w = 0; w < worlds; ++w) {
        StoredWorld stored;
        stored.world_index = static_cast<uint64_t>(w);
        stored.frame_count = kFrames;
        stored.polyline_points = kPointsPerPath;
        stored.polyline_stride = 4;
        stored.tracks.resize(static_cast<size_t>(bodies));
        const std::vector<double> track = tumbling_track(random);
        stored.tracks[posed_body].rotation =
            encode_rotation_track(track.data(), kFrames, CodecBounds{}.rotation_error_max_rad);
        rotations->add(stored.world_index, std::move(stored));
    }
    index.set_rotation_source(rotations);
    // Adding a part: its first query decodes the rotations (each try a new tolerance, so a new part).
    auto goal_with_pose = [&](double within_deg) {
        OrientationPartSpec upright;
        upright.bodies = {posed_body};
        upright.within_deg = within_deg;
        upright.time_window = std::make_pair(9.0, 10.0);
        std::vector<QueryBox> goal = boxes;
        goal.push_back(make_orientation_part(upright));
        return goal;
    };
    double added_s = 1e9;
    size_t added_matches = 0;
    for (double within_deg : {20.0, 21.0, 22.0}) {
        const std::vector<QueryBox> goal = goal_with_pose(within_deg);
        start = std::chrono::steady_clock::now();
        added_matches = index.query(goal, 0, false, 0).matching.size();
        added_s = std::min(added_s, seconds_since(start));
    }
    report("pose_part_added_ms_" + size, added_s * 1000, "ms",
           "all cores; the match count once a pose part (one body upright in the last second) joins the two "
           "boxes (target < 500 ms); " + std::to_string(added_matches) + " matches");
    // Dragging a box while it stays: the same goal again, against the two boxes alone.
    auto best_of_5 = [&](const std::vector<QueryBox>& goal) {
        double best = 1e9;
        for (int repeat = 0; repeat < 5; ++repeat) {
            start = std::chrono::steady_clock::now();
            index.query(goal, 0, false, 0);
            best = std::min(best, seconds_since(start));
        }
        return best;
    };
    const double drag_s = best_of_5(goal_with_pose(22.0));
    const double boxes_s = best_of_5(boxes);
    report("pose_part_drag_ratio", drag_s / boxes_s, "x",
           "a query of the two boxes beside a pose part asked before / the two boxes alone, all cores");
    return 0;
}
