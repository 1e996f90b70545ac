#include "sampler/Sampler.h"

#include <omp.h>

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <sstream>

#include "sampler/InOrderDelivery.h"
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

// Worlds a thread may run ahead of the first one not yet delivered, per thread: bounds the
// finished worlds held for the reorder window (a staircase world is 30 MB) when one is slow.
constexpr size_t kWindowWorldsPerThread = 8;

// Runs make_world(k, cancel, thread) for k in [0, count) on `threads` threads and delivers each
// result in the order of k (a reorder window), never concurrently; the statistics count every
// outcome.
template <typename MakeWorld>
SamplingStatistics run_parallel(size_t count, int threads, const WorldSink& sink, SamplingProgress* progress,
                                MakeWorld make_world) {
    const auto start = std::chrono::steady_clock::now();
    initialize_ode_once();
    SamplingStatistics stats;
    std::mutex sink_mutex;
    std::condition_variable delivered;
    std::exception_ptr sink_error;
    std::atomic<bool> stop_for_error{false};
    const std::atomic<bool>* cancel = progress ? &progress->cancel : nullptr;
    const int thread_count = thread_count_for(threads);
    const size_t window = kWindowWorldsPerThread * static_cast<size_t>(thread_count);
    InOrderDelivery<WorldResult> in_order([&](WorldResult&& world) {
        // An exception must not escape an OpenMP region; stop the run and rethrow after it.
        try {
            if (!sink_error) sink(std::move(world));
        } catch (...) {
            sink_error = std::current_exception();
            stop_for_error = true;
        }
    });
    const auto total = static_cast<long long>(count);
    // Dynamic scheduling: world lengths vary a lot (early rest, rejections). Worlds are handed out
    // in order, so the one every waiting thread waits for is always running.
#pragma omp parallel for num_threads(thread_count) schedule(dynamic, 1)
    for (long long k = 0; k < total; ++k) {
        const auto position = static_cast<size_t>(k);
        {
            std::unique_lock<std::mutex> lock(sink_mutex);
            delivered.wait(lock, [&] { return position < in_order.next() + window; });
        }
        WorldResult world;
        const bool skipped = (cancel && cancel->load(std::memory_order_relaxed)) || stop_for_error.load();
        if (!skipped) world = make_world(position, cancel, omp_get_thread_num());
        std::lock_guard<std::mutex> lock(sink_mutex);
        if (skipped) {
            in_order.skip(position);
        } else {
            switch (world.status) {
                case WorldStatus::Ok: ++stats.worlds_ok; break;
                case WorldStatus::Rejected:
                    ++stats.worlds_rejected;
                    ++stats.reject_reasons[world.reject_reason];
                    break;
                case WorldStatus::Cancelled: ++stats.worlds_cancelled; break;
            }
            note_ode_messages(stats.ode_messages, world.world_index, world.ode_messages);
            if (progress) progress->worlds_done.fetch_add(1, std::memory_order_relaxed);
            in_order.arrive(position, std::move(world));
        }
        delivered.notify_all();
    }
    if (sink_error) std::rethrow_exception(sink_error);
    stats.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

}  // namespace

void note_ode_messages(OdeMessageReports& reports, uint64_t world_index, const std::vector<OdeMessage>& messages) {
    for (const OdeMessage& m : messages)
        merge_ode_messages(reports, {{m.code, {m.text, world_index, m.first_time_s, 1}}});
}

void merge_ode_messages(OdeMessageReports& into, const OdeMessageReports& from) {
    for (const auto& [code, report] : from) {
        const auto [it, added] = into.emplace(code, report);
        if (added) continue;
        it->second.worlds += report.worlds;
        if (report.first_world < it->second.first_world) {
            it->second.text = report.text;
            it->second.first_world = report.first_world;
            it->second.first_time_s = report.first_time_s;
        }
    }
}

std::string describe_ode_messages(const OdeMessageReport& report) {
    std::ostringstream text;
    text.precision(3);
    text << "ODE said \"" << report.text << "\" in " << report.worlds << (report.worlds == 1 ? " world" : " worlds")
         << " (first world " << report.first_world << " at " << report.first_time_s
         << " s); they are stored, but their contacts at those steps may be off";
    return text.str();
}

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
