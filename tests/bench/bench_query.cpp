// Query benchmarks over synthetic paths shaped like sampled ones: bodies thrown, bouncing on
// the ground and coming to rest, 1,500 worlds × 200 bodies × 10 s at 30 Hz.
#include <chrono>
#include <cstdlib>
#include <vector>

#include "BenchReport.h"
#include "common/QuantizedPolyline.h"
#include "query/PathIndex.h"
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
    return 0;
}
