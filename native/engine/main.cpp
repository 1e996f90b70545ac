// mwb-engine: samples worlds into a library file, and inspects and merges libraries. Blender's
// add-on runs it as a child process; farm tasks run it (through Blender's CLI) per seed chunk.
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include <omp.h>
#ifndef _WIN32
#include <unistd.h>
#endif

#include "EngineOptions.h"
#ifndef _WIN32
#include "SupervisedSampler.h"
#include "WorldWorker.h"
#endif
#include "common/BuildInfo.h"
#include "library/ByteIO.h"
#include "library/LibraryReader.h"
#include "library/LibraryFormat.h"
#include "library/LibraryMerge.h"
#include "library/LibraryWriter.h"
#include "refine/StoredWorldRefinement.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "seek/GoalJson.h"
#include "seek/GoalSearch.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

SamplingProgress g_progress;

void request_cancel(int) { g_progress.cancel.store(true); }

#ifdef _WIN32
// Worker processes need fork: on Windows every world is simulated in the engine's own process,
// as with --in-process (a world that crashes ODE ends the run there).
constexpr bool kWorkerProcesses = false;
#else
constexpr bool kWorkerProcesses = true;

// The engine executable itself, for its worker processes.
std::string own_executable() {
    char path[4096];
    const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
    if (n <= 0) throw std::runtime_error("cannot find the engine executable (/proc/self/exe)");
    return std::string(path, static_cast<size_t>(n));
}
#endif

int run_sample(const EngineOptions& options, [[maybe_unused]] const std::vector<std::string>& args) {
    Scene scene = load_scene_file(options.scene_path);
    RunHeader header{scene_to_json(scene), options.parameters, options.bounds, options.base_seed, engine_build()};
    CompiledScene compiled(std::move(scene), options.parameters);
    if (options.dry_run) {
        // What a front end asks before it samples: may this run go into that library?
        std::string library = "new";
        if (std::ifstream(options.output_path).good())
            library = run_hash(LibraryReader(options.output_path).header()) == run_hash(header) ? "same" : "other";
        std::cout << "library " << library << " run " << run_hash(header) << "\n";
        return 0;
    }
    LibraryWriter writer(options.output_path, header);
    for (const std::string& repair : writer.repairs()) std::cerr << "mwb-engine: " << repair << "\n";
    if (writer.header().engine_build != header.engine_build)
        std::cerr << "mwb-engine: warning: " << options.output_path << " was sampled by "
                  << describe_build(writer.header().engine_build) << "; this engine is " << engine_build()
                  << ": worlds it adds may not reproduce with the other build\n";
    // Worlds already in the file are kept, so an interrupted run resumes where it stopped.
    const std::set<uint64_t> present(writer.existing_world_indices().begin(), writer.existing_world_indices().end());
    std::vector<uint64_t> todo;
    for (uint64_t k = 0; k < options.world_count; ++k)
        if (!present.count(options.first_world + k)) todo.push_back(options.first_world + k);
    std::signal(SIGINT, request_cancel);
    std::signal(SIGTERM, request_cancel);
    uint64_t stored = 0;
    auto report = [&](uint64_t world_index) {
        ++stored;
        if (options.progress) {
            std::cerr << "MWB-PROGRESS " << stored << " " << todo.size() << " world " << world_index << "\n";
            std::cerr.flush();
        }
    };
    SamplingStatistics stats;
    if (options.in_process || !kWorkerProcesses) {
        stats = sample_world_list(
            compiled, options.base_seed, todo, options.threads,
            [&](WorldResult&& world) {
                writer.append(world);
                if (world.status != WorldStatus::Cancelled) report(world.world_index);
            },
            &g_progress, options.share_prefix);
    } else {
#ifndef _WIN32
        // Each world in a worker process: a world that crashes ODE is rejected, the run goes on.
        SupervisedRun run{own_executable(), args, options.threads > 0 ? options.threads : omp_get_max_threads(),
                          options.base_seed, options.world_time_limit_s};
        run.worker_args[0] = "worker";
        stats = sample_supervised(run, todo, writer, [&](uint64_t world_index, bool) { report(world_index); },
                                  g_progress.cancel);
#endif
    }
    std::cout << "sampled " << stats.worlds_ok << " worlds, rejected " << stats.worlds_rejected << ", skipped "
              << present.size() << " already stored" << (g_progress.cancel ? ", cancelled" : "") << " in "
              << stats.wall_time_s << " s -> " << options.output_path << "\n";
    for (const auto& [reason, count] : stats.reject_reasons) std::cout << "  rejected " << count << ": " << reason << "\n";
    return g_progress.cancel ? 130 : 0;
}

std::string describe_change(const EngineOptions& options, const RefineOutcome& outcome, double record_hz) {
    if (outcome.added.empty() && outcome.removed.empty()) {
        std::ostringstream at;
        at << "at " << outcome.branch_frame / record_hz << " s";
        return at.str();
    }
    std::string text;
    auto join = [&](const char* verb, const std::vector<std::string>& names) {
        if (names.empty()) return;
        text += (text.empty() ? "" : ", ") + std::string(verb) + " ";
        for (size_t k = 0; k < names.size(); ++k) text += (k ? ", " : "") + names[k];
    };
    join("adding", options.add_bodies);
    join("removing", options.remove_bodies);
    join("updating", options.update_bodies);
    return text;
}

// Refines one stored world (see refine_stored_world): `count` children that branch at the given
// time, or that add or remove bodies from t = 0.
int run_refine(const EngineOptions& options) {
    const LibraryReader reader(options.output_path);
    RefineRequest request;
    request.parent_world = options.parent_world;
    request.bodies = options.bodies;
    request.branch_time_s = options.branch_time_s;
    request.count = options.world_count;
    request.first_child = options.first_child;
    request.add = options.add_bodies;
    request.remove = options.remove_bodies;
    request.update = options.update_bodies;
    if (!options.scene_path.empty()) request.source_scene = load_scene_file(options.scene_path);
    request.threads = options.threads;
    LibraryWriter writer(options.output_path, reader.header());
    std::signal(SIGINT, request_cancel);
    std::signal(SIGTERM, request_cancel);
    uint64_t stored = 0;
    const RefineOutcome outcome = refine_stored_world(
        reader, request, writer,
        [&](WorldResult&& world) {
            if (world.status != WorldStatus::Cancelled) ++stored;
            if (options.progress) {
                std::cerr << "MWB-PROGRESS " << stored << " " << request.count << " world " << world.world_index << "\n";
                std::cerr.flush();
            }
        },
        &g_progress);
    const SamplingStatistics& stats = outcome.statistics;
    std::cout << "refined world " << options.parent_world << " "
              << describe_change(options, outcome, reader.header().parameters.record_hz) << " into worlds "
              << outcome.first_child << ".." << outcome.first_child + options.world_count - 1 << ": " << stats.worlds_ok
              << " stored, " << stats.worlds_rejected << " rejected in " << stats.wall_time_s << " s\n";
    return g_progress.cancel ? 130 : 0;
}

std::string with_commas(uint64_t n) {
    std::string digits = std::to_string(n), out;
    for (size_t k = 0; k < digits.size(); ++k) {
        if (k && (digits.size() - k) % 3 == 0) out += ',';
        out += digits[k];
    }
    return out;
}

// Searches the library for worlds meeting a goal (see GoalSearch.h), appending every world it
// makes; progress lines let a front end show the best world as it improves.
int run_seek(const EngineOptions& options) {
    std::ifstream goal_file(options.goal_path);
    if (!goal_file) throw GoalError("cannot read the goal file " + options.goal_path);
    const std::string goal_text((std::istreambuf_iterator<char>(goal_file)), std::istreambuf_iterator<char>());
    SeekRequest request;
    {
        const LibraryReader reader(options.output_path);
        request.boxes = goal_from_json(goal_text, scene_from_json(reader.scene_json()));
    }
    request.want = options.want;
    request.budget_worlds = options.budget_worlds;
    request.budget_s = options.budget_s;
    request.seed = options.base_seed;
    request.threads = options.threads;
    std::signal(SIGINT, request_cancel);
    std::signal(SIGTERM, request_cancel);
    const SeekOutcome outcome = seek_goal(
        options.output_path, request,
        [&](const SeekStatus& s) {
            if (!options.progress) return;
            std::cerr << "MWB-SEEK " << s.best_boxes_met << " " << s.box_count << " " << s.worlds_made << " "
                      << s.best_world << " " << s.worlds_meeting_goal << "\n";
            std::cerr.flush();
        },
        &g_progress);
    if (options.json) {
        nlohmann::json j{{"reached", outcome.reached},         {"found", outcome.found},
                         {"best", outcome.best_world},         {"best_boxes_met", outcome.best_boxes_met},
                         {"boxes", outcome.box_count},         {"worlds_made", outcome.worlds_made},
                         {"refinements", outcome.refinements}, {"seconds", outcome.seconds},
                         {"cancelled", outcome.cancelled}};
        std::cout << j.dump() << "\n";
    } else {
        std::ostringstream made;
        made.precision(1);
        made << std::fixed << " (" << with_commas(outcome.worlds_made) << " worlds made in " << outcome.seconds << " s)";
        if (outcome.reached) {
            std::cout << "seek: " << outcome.found.size() << (outcome.found.size() == 1 ? " world meets" : " worlds meet")
                      << " all " << outcome.box_count << " boxes:";
            for (size_t k = 0; k < outcome.found.size() && k < 20; ++k) std::cout << (k ? ", " : " ") << outcome.found[k];
            if (outcome.found.size() > 20) std::cout << ", ...";
            std::cout << made.str() << "\n";
        } else {
            std::cout << "seek: " << (outcome.cancelled ? "cancelled" : "budget spent") << "; best world "
                      << outcome.best_world << " meets " << outcome.best_boxes_met << " of " << outcome.box_count
                      << " boxes";
            if (!outcome.found.empty()) std::cout << " (" << outcome.found.size() << " of " << options.want << " wanted found)";
            std::cout << made.str() << "\n";
        }
    }
    return outcome.cancelled ? 130 : 0;
}

int run_info(const EngineOptions& options) {
    const LibraryReader reader(options.inputs[0]);
    const Scene scene = scene_from_json(reader.scene_json());
    uint64_t motion_bytes = 0, body_frames = 0;
    for (const StoredWorld& w : reader.worlds()) {
        // What the file holds: each world's own tracks (inherited ones are its parent's).
        for (const StoredTrack& t : w.tracks) {
            if (!t.present || t.inherited) continue;
            motion_bytes += t.position.size() + t.rotation.size();
            body_frames += w.frame_count;
        }
    }
    std::map<std::string, uint64_t> reasons;
    for (const StoredRejection& r : reader.rejections()) ++reasons[r.reason];
    nlohmann::json j{{"path", reader.path()},
                     {"worlds", reader.worlds().size()},
                     {"rejected", reader.rejections().size()},
                     {"rejected_reasons", reasons},
                     {"bodies", scene.bodies.size()},
                     {"file_bytes", reader.file_size()},
                     {"motion_bytes", motion_bytes},
                     {"motion_bytes_per_body_frame", body_frames ? double(motion_bytes) / double(body_frames) : 0.0},
                     {"scene_hash", scene_hash(reader.header())},
                     {"run_hash", run_hash(reader.header())},
                     {"base_seed", reader.header().base_seed},
                     {"run", nlohmann::json::parse(run_settings_to_json(reader.header()))},
                     {"scene_revision", reader.scene_revision()},
                     {"engine_build", reader.header().engine_build},
                     {"warnings", reader.warnings()}};
    if (options.json) {
        std::cout << j.dump(2) << "\n";
        return 0;
    }
    std::cout << reader.path() << ": " << reader.worlds().size() << " worlds, " << reader.rejections().size()
              << " rejected, " << scene.bodies.size() << " bodies, " << reader.file_size() << " bytes, "
              << j["motion_bytes_per_body_frame"].get<double>() << " motion bytes per body-frame, scene "
              << scene_hash(reader.header()) << "\n";
    std::cout << "  made by " << describe_build(reader.header().engine_build) << "\n";
    for (const auto& [reason, count] : reasons) std::cout << "  rejected " << count << ": " << reason << "\n";
    for (const std::string& w : reader.warnings()) std::cout << "  warning: " << w << "\n";
    return 0;
}

int run_merge(const EngineOptions& options) {
    for (const std::string& warning : merge_libraries(options.inputs, options.output_path))
        std::cerr << "mwb-engine: warning: " << warning << "\n";
    const LibraryReader merged(options.output_path);
    std::cout << "merged " << options.inputs.size() << " libraries: " << merged.worlds().size() << " worlds -> "
              << options.output_path << "\n";
    return 0;
}

int run_validate(const EngineOptions& options) {
    const Scene scene = load_scene_file(options.inputs[0]);
    std::cout << options.inputs[0] << ": valid scene '" << scene.name << "', " << scene.bodies.size() << " bodies, "
              << scene.constraints.size() << " constraints\n";
    return 0;
}

int run(const std::vector<std::string>& args) {
    const EngineOptions options = parse_engine_options(args);
    if (options.command == "sample") return run_sample(options, args);
#ifdef _WIN32
    if (options.command == "worker") throw UsageError("worker processes are not available on Windows");
#else
    if (options.command == "worker") return run_world_worker(options);
#endif
    if (options.command == "refine") return run_refine(options);
    if (options.command == "seek") return run_seek(options);
    if (options.command == "info") return run_info(options);
    if (options.command == "merge") return run_merge(options);
    return run_validate(options);
}

}  // namespace
}  // namespace mwb

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    try {
        return mwb::run(args);
    } catch (const mwb::UsageError& error) {
        std::cerr << "mwb-engine: " << error.what() << "\n" << mwb::engine_usage();
        return 2;
    } catch (const mwb::RefineError& error) {
        std::cerr << "mwb-engine: " << error.what() << "\n";
        return 2;
    } catch (const mwb::GoalError& error) {
        std::cerr << "mwb-engine: " << error.what() << "\n";
        return 2;
    } catch (const mwb::SceneError& error) {
        std::cerr << "mwb-engine: invalid scene:\n" << error.what() << "\n";
        return 3;
    } catch (const mwb::LibraryError& error) {
        std::cerr << "mwb-engine: " << error.what() << "\n";
        return 4;
    } catch (const std::exception& error) {
        std::cerr << "mwb-engine: " << error.what() << "\n";
        return 1;
    }
}
