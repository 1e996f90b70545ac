#include "sampler/Sampler.h"

#include <omp.h>

#include <chrono>
#include <exception>
#include <mutex>

#include "sim/OdeWorld.h"
#include "sim/SharedPrefix.h"
#include "sim/WorldSimulator.h"

namespace mwb {

SamplingStatistics sample_worlds(const CompiledScene& compiled, uint64_t base_seed, uint64_t first_world,
                                 uint64_t world_count, int threads, const WorldSink& sink,
                                 SamplingProgress* progress, bool share_prefix) {
    std::vector<uint64_t> indices(world_count);
    for (uint64_t k = 0; k < world_count; ++k) indices[k] = first_world + k;
    return sample_world_list(compiled, base_seed, indices, threads, sink, progress, share_prefix);
}

namespace {

int thread_count_for(int threads) { return threads > 0 ? threads : omp_get_max_threads(); }

// Runs make_world(k, cancel, thread) for k in [0, count) on `threads` threads and delivers each
// result in completion order, never concurrently; the statistics count every outcome.
template <typename MakeWorld>
SamplingStatistics run_parallel(size_t count, int threads, const WorldSink& sink, SamplingProgress* progress,
                                MakeWorld make_world) {
    const auto start = std::chrono::steady_clock::now();
    initialize_ode_once();
    SamplingStatistics stats;
    std::mutex sink_mutex;
    std::exception_ptr sink_error;
    std::atomic<bool> stop_for_error{false};
    const std::atomic<bool>* cancel = progress ? &progress->cancel : nullptr;
    const int thread_count = thread_count_for(threads);
    const auto total = static_cast<long long>(count);
    // Dynamic scheduling: world lengths vary a lot (early rest, rejections).
#pragma omp parallel for num_threads(thread_count) schedule(dynamic, 1)
    for (long long k = 0; k < total; ++k) {
        if ((cancel && cancel->load(std::memory_order_relaxed)) || stop_for_error.load()) continue;
        WorldResult world = make_world(static_cast<size_t>(k), cancel, omp_get_thread_num());
        std::lock_guard<std::mutex> lock(sink_mutex);
        switch (world.status) {
            case WorldStatus::Ok: ++stats.worlds_ok; break;
            case WorldStatus::Rejected:
                ++stats.worlds_rejected;
                ++stats.reject_reasons[world.reject_reason];
                break;
            case WorldStatus::Cancelled: ++stats.worlds_cancelled; break;
        }
        // An exception must not escape an OpenMP region; stop the run and rethrow after it.
        try {
            if (!sink_error) sink(std::move(world));
        } catch (...) {
            sink_error = std::current_exception();
            stop_for_error = true;
        }
        if (progress) progress->worlds_done.fetch_add(1, std::memory_order_relaxed);
    }
    if (sink_error) std::rethrow_exception(sink_error);
    stats.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

}  // namespace

SamplingStatistics sample_world_list(const CompiledScene& compiled, uint64_t base_seed,
                                     const std::vector<uint64_t>& world_indices, int threads, const WorldSink& sink,
                                     SamplingProgress* progress, bool share_prefix) {
    // Each thread shares the prefix of the first world it simulates with the later ones: no
    // thread waits for another, and any split of the indices gives the same worlds.
    std::vector<PrefixSharingSimulator> simulators;
    for (int t = 0; t < thread_count_for(threads); ++t) simulators.emplace_back(compiled, base_seed, share_prefix);
    return run_parallel(world_indices.size(), threads, sink, progress,
                        [&](size_t k, const std::atomic<bool>* cancel, int thread) {
                            return simulators[static_cast<size_t>(thread)].simulate(world_indices[k], cancel);
                        });
}

SamplingStatistics refine_worlds(const CompiledScene& compiled, uint64_t base_seed, const std::vector<WorldResult>& chain,
                                 const std::vector<RefineStep>& children, int threads, const WorldSink& sink,
                                 SamplingProgress* progress) {
    for (const RefineStep& child : children) check_refinement(compiled, chain, child);
    return run_parallel(children.size(), threads, sink, progress,
                        [&](size_t k, const std::atomic<bool>* cancel, int) {
                            return refine_world(compiled, base_seed, chain, children[k], cancel);
                        });
}

}  // namespace mwb
