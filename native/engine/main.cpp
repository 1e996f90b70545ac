// mwb-engine: samples worlds into a library file, and inspects and merges libraries. Blender's
// add-on runs it as a child process; farm tasks run it (through Blender's CLI) per seed chunk.
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include <omp.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "EngineEvents.h"
#include "EngineOptions.h"
#include "RunWords.h"
#include "SupervisedSampler.h"
#include "WorkerProcess.h"
#include "WorldWorker.h"
#include "common/BuildInfo.h"
#include "common/EngineProtocol.h"
#include "library/ByteIO.h"
#include "library/LibraryReader.h"
#include "library/LibraryFormat.h"
#include "library/LibraryMerge.h"
#include "library/LibraryWriter.h"
#include "refine/StoredWorldRefinement.h"
#include "refine/WorldMaker.h"
#include "sampler/Sampler.h"
#include "scene/SceneJson.h"
#include "seek/GoalJson.h"
#include "seek/GoalSearch.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

SamplingProgress g_progress;

void request_cancel(int) { g_progress.cancel.store(true); }

// How the engine was started (argv[0]), for finding itself without /proc.
std::string g_invoked_as;

// The engine executable the worker processes run, or empty when the worlds are simulated in this
// process instead (a world that crashes ODE then ends the run): with --in-process, and, after one
// warning, when the executable cannot be found.
std::string executable_for_workers(const EngineOptions& options, EngineEvents& events) {
    if (options.in_process) return {};
    std::string path = engine_executable(g_invoked_as);
    if (path.empty())
        events.warning(EngineWarningCode::InProcess,
                       "cannot find the engine executable (no /proc, and '" + g_invoked_as +
                           "' is not on PATH): worlds are simulated in this process, where one that crashes ODE ends the run");
    return path;
}

// Ctrl-C, or "cancel" on stdin for a program (EngineProtocol.h): finish the record being
// written, keep every finished world, exit with EngineExit::Cancelled.
void listen_for_cancel(const EngineOptions& options) {
    std::signal(SIGINT, request_cancel);
    std::signal(SIGTERM, request_cancel);
    if (options.events) listen_for_cancel_on_stdin(g_progress.cancel);
}

// Where a refinement's or a search's worlds are simulated: each in a supervised worker process
// reading the library, so that one that crashes ODE is rejected and the rest go on; with
// --in-process on this process's threads.
std::unique_ptr<WorldMaker> world_maker(const EngineOptions& options, uint64_t base_seed, size_t cache_bytes,
                                        EngineEvents& events) {
    const std::string engine = executable_for_workers(options, events);
    if (engine.empty()) return std::make_unique<InProcessWorlds>(options.threads, cache_bytes);
    const int workers = options.threads > 0 ? options.threads : omp_get_max_threads();
    SupervisedRun run{engine, {"worker", "--library", options.library_path, "--threads", std::to_string(workers)},
                      workers, base_seed, options.world_time_limit_s};
    return std::make_unique<SupervisedWorlds>(std::move(run));
}

// One warning per kind of message ODE gave while the command's worlds stepped.
void warn_of_ode_messages(EngineEvents& events, const OdeMessageReports& reports) {
    for (const auto& [code, report] : reports) events.warning(EngineWarningCode::OdeMessage, describe_ode_messages(report));
}

int exit_status(bool cancelled) {
    return static_cast<int>(cancelled ? EngineExit::Cancelled : EngineExit::Ok);
}

int run_sample(const EngineOptions& options, [[maybe_unused]] const std::vector<std::string>& args,
               EngineEvents& events) {
    // The scene is parsed once here; the header, the writer and the simulation share it.
    Scene scene = load_scene_file(options.scene_path);
    RunHeader header{scene_to_json(scene), options.parameters, options.bounds, options.base_seed, engine_build()};
    const Vec3 gravity = scene.world.gravity;
    CompiledScene compiled(std::move(scene), options.parameters);
    LibraryWriter writer(options.output_path, header, gravity);
    for (const std::string& repair : writer.repairs()) events.warning(EngineWarningCode::Repaired, repair);
    if (writer.header().engine_build != header.engine_build)
        events.warning(EngineWarningCode::OtherBuild,
                       options.output_path + " was sampled by " + describe_build(writer.header().engine_build) +
                           "; this engine is " + engine_build() + ": worlds it adds may not reproduce with the other build");
    // Worlds already in the file are kept, so an interrupted run resumes where it stopped.
    const std::set<uint64_t> present(writer.existing_world_indices().begin(), writer.existing_world_indices().end());
    std::vector<uint64_t> todo;
    for (uint64_t k = 0; k < options.world_count; ++k)
        if (!present.count(options.first_world + k)) todo.push_back(options.first_world + k);
    listen_for_cancel(options);
    uint64_t finished = 0;
    auto report = [&](uint64_t world_index, bool stored, const std::string& reason) {
        ++finished;
        events.world(world_index, stored, reason);
        events.progress(finished, todo.size(), {}, worlds_done_text("sampled", finished, todo.size()));
    };
    SamplingStatistics stats;
    const std::string engine = executable_for_workers(options, events);
    if (engine.empty()) {
        stats = sample_world_list(
            compiled, options.base_seed, todo, options.threads,
            [&](WorldResult&& world) {
                writer.append(world);
                if (world.status != WorldStatus::Cancelled)
                    report(world.world_index, world.status == WorldStatus::Ok, world.reject_reason);
            },
            &g_progress, options.share_prefix);
    } else {
        // Each world in a worker process: a world that crashes ODE is rejected, the run goes on.
        SupervisedRun run{engine, args, options.threads > 0 ? options.threads : omp_get_max_threads(),
                          options.base_seed, options.world_time_limit_s};
        run.worker_args[0] = "worker";
        stats = sample_supervised(run, todo, writer, report, g_progress.cancel);
    }
    const bool cancelled = g_progress.cancel;
    std::ostringstream text;
    text << "sampled " << stats.worlds_ok << " worlds, rejected " << stats.worlds_rejected << ", skipped "
         << present.size() << " already stored" << (cancelled ? ", cancelled" : "") << " in " << stats.wall_time_s
         << " s -> " << options.output_path << "\n";
    const std::string lost = rejections_text(stats.worlds_rejected, stats.reject_reasons);
    if (!lost.empty()) text << "  " << lost << "\n";
    warn_of_ode_messages(events, stats.ode_messages);
    events.summary({{"library", options.output_path},
                    {"stored", stats.worlds_ok},
                    {"rejected", stats.worlds_rejected},
                    {"skipped", present.size()},
                    {"cancelled", cancelled},
                    {"seconds", stats.wall_time_s},
                    {"reject_reasons", stats.reject_reasons},
                    {"rejected_text", lost},
                    {"scene_parses", scene_parses_in_this_process()}},
                   text.str());
    return exit_status(cancelled);
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
int run_refine(const EngineOptions& options, EngineEvents& events) {
    const LibraryReader reader(options.library_path);
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
    LibraryWriter writer(options.library_path, reader.header());
    listen_for_cancel(options);
    uint64_t finished = 0;
    const std::unique_ptr<WorldMaker> maker = world_maker(options, reader.header().base_seed, 0, events);
    const RefineOutcome outcome = refine_stored_world(
        reader, request, writer, *maker,
        [&](uint64_t world_index, bool stored, const std::string& reason) {
            ++finished;
            events.world(world_index, stored, reason);
            events.progress(finished, request.count, {}, worlds_done_text("refined", finished, request.count));
        },
        &g_progress);
    const SamplingStatistics& stats = outcome.statistics;
    std::ostringstream text;
    text << "refined world " << options.parent_world << " "
         << describe_change(options, outcome, reader.header().parameters.record_hz) << " into worlds "
         << outcome.first_child << ".." << outcome.first_child + options.world_count - 1 << ": " << stats.worlds_ok
         << " stored, " << stats.worlds_rejected << " rejected in " << stats.wall_time_s << " s";
    const std::string lost = rejections_text(stats.worlds_rejected, stats.reject_reasons);
    if (!lost.empty()) text << "\n  " << lost;
    warn_of_ode_messages(events, stats.ode_messages);
    events.summary({{"parent", options.parent_world},
                    {"first_child", outcome.first_child},
                    {"count", options.world_count},
                    {"stored", stats.worlds_ok},
                    {"rejected", stats.worlds_rejected},
                    {"reject_reasons", stats.reject_reasons},
                    {"rejected_text", lost},
                    {"cancelled", bool(g_progress.cancel)},
                    {"seconds", stats.wall_time_s}},
                   text.str());
    return exit_status(g_progress.cancel);
}

// Searches the library for worlds meeting a goal (see GoalSearch.h), appending every world it
// makes; progress events let a front end show the best world as it improves.
int run_seek(const EngineOptions& options, EngineEvents& events) {
    std::ifstream goal_file(options.goal_path);
    if (!goal_file) throw GoalError("cannot read the goal file " + options.goal_path);
    const std::string goal_text((std::istreambuf_iterator<char>(goal_file)), std::istreambuf_iterator<char>());
    SeekRequest request;
    {
        const LibraryReader reader(options.library_path);
        request.boxes = goal_from_json(goal_text, scene_from_json(reader.scene_json()));
    }
    request.want = options.want;
    request.budget_worlds = options.budget_worlds;
    request.budget_s = options.budget_s;
    request.seed = options.base_seed;
    request.threads = options.threads;
    listen_for_cancel(options);
    const std::unique_ptr<WorldMaker> maker =
        world_maker(options, read_run_header(options.library_path).base_seed, request.cache_bytes, events);
    // Progress goes out as each world arrives, not only after each batch: a batch of slow worlds
    // still shows the count moving. The best world is the last batch's.
    SeekStatus last;
    uint64_t arrived_since_status = 0;
    auto report = [&](const SeekStatus& s) {
        events.progress(s.worlds_made, options.budget_worlds,
                        {{"seek",
                          {{"boxes_met", s.best_boxes_met},
                           {"box_count", s.box_count},
                           {"worlds_made", s.worlds_made},
                           {"worlds_rejected", s.worlds_rejected},
                           {"best_world", s.best_world},
                           {"worlds_meeting_goal", s.worlds_meeting_goal}}}},
                        seek_progress_text(s));
    };
    const SeekOutcome outcome = seek_goal(
        options.library_path, request,
        [&](const SeekStatus& s) {
            last = s;
            arrived_since_status = 0;
            report(s);
        },
        &g_progress, maker.get(),
        [&](uint64_t world_index, bool stored, const std::string& reason) {
            events.world(world_index, stored, reason);
            SeekStatus now = last;
            now.worlds_made += ++arrived_since_status;
            now.worlds_rejected += stored ? 0 : 1;
            last.worlds_rejected = now.worlds_rejected;
            report(now);
        });
    const nlohmann::json fields{{"reached", outcome.reached},         {"found", outcome.found},
                                {"best", outcome.best_world},         {"best_boxes_met", outcome.best_boxes_met},
                                {"boxes", outcome.box_count},         {"worlds_made", outcome.worlds_made},
                                {"refinements", outcome.refinements}, {"seconds", outcome.seconds},
                                {"cancelled", outcome.cancelled},     {"rejected", outcome.worlds_rejected},
                                {"reject_reasons", outcome.reject_reasons},
                                {"rejected_text", rejections_text(outcome.worlds_rejected, outcome.reject_reasons)}};
    warn_of_ode_messages(events, outcome.ode_messages);
    events.summary(fields, options.json ? fields.dump() : seek_outcome_text(outcome, options.want));
    return exit_status(outcome.cancelled);
}

int run_info(const EngineOptions& options, EngineEvents& events) {
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
    std::ostringstream text;
    if (options.json) {
        text << j.dump(2);
    } else {
        text << reader.path() << ": " << reader.worlds().size() << " worlds, " << reader.rejections().size()
             << " rejected, " << scene.bodies.size() << " bodies, " << reader.file_size() << " bytes, "
             << j["motion_bytes_per_body_frame"].get<double>() << " motion bytes per body-frame, scene "
             << scene_hash(reader.header()) << "\n";
        text << "  made by " << describe_build(reader.header().engine_build) << "\n";
        for (const auto& [reason, count] : reasons) text << "  rejected " << count << ": " << reason << "\n";
        for (const std::string& w : reader.warnings()) text << "  warning: " << w << "\n";
    }
    events.summary(std::move(j), text.str());
    return 0;
}

int run_merge(const EngineOptions& options, EngineEvents& events) {
    for (const std::string& warning : merge_libraries(options.inputs, options.output_path))
        events.warning(EngineWarningCode::Merge, warning);
    const LibraryReader merged(options.output_path);
    std::ostringstream text;
    text << "merged " << options.inputs.size() << " libraries: " << merged.worlds().size() << " worlds -> "
         << options.output_path;
    events.summary({{"inputs", options.inputs.size()}, {"worlds", merged.worlds().size()}, {"library", options.output_path}},
                   text.str());
    return 0;
}

int run_validate(const EngineOptions& options, EngineEvents& events) {
    const Scene scene = load_scene_file(options.inputs[0]);
    std::ostringstream text;
    text << options.inputs[0] << ": valid scene '" << scene.name << "', " << scene.bodies.size() << " bodies, "
         << scene.constraints.size() << " constraints";
    events.summary({{"scene", scene.name}, {"bodies", scene.bodies.size()}, {"constraints", scene.constraints.size()}},
                   text.str());
    return 0;
}

int run(const EngineOptions& options, const std::vector<std::string>& args, EngineEvents& events) {
    if (options.command == "sample") return run_sample(options, args, events);
    if (options.command == "worker") return run_world_worker(options);
    if (options.command == "refine") return run_refine(options, events);
    if (options.command == "seek") return run_seek(options, events);
    if (options.command == "info") return run_info(options, events);
    if (options.command == "merge") return run_merge(options, events);
    return run_validate(options, events);
}

// The lines of a SceneError: each one problem.
std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (!line.empty()) lines.push_back(line);
    return lines;
}

// Runs the command; every failure becomes one error event and its EngineExit.
int run_reporting_failures(const std::vector<std::string>& args, EngineEvents& events) {
    auto fail = [&](EngineErrorCode code, EngineExit exit, const std::string& message) {
        events.error(code, message);
        return static_cast<int>(exit);
    };
    try {
        const EngineOptions options = parse_engine_options(args);
        events.start(options.command);
        return run(options, args, events);
    } catch (const UsageError& error) {
        const int status = fail(EngineErrorCode::Usage, EngineExit::Usage, error.what());
        if (!events.as_json()) std::cerr << engine_usage();
        return status;
    } catch (const RefineError& error) {
        return fail(EngineErrorCode::Refine, EngineExit::Usage, error.what());
    } catch (const GoalError& error) {
        return fail(EngineErrorCode::Goal, EngineExit::Usage, error.what());
    } catch (const SceneError& error) {
        const std::vector<std::string> problems = lines_of(error.what());
        events.error(EngineErrorCode::InvalidScene, "invalid scene: " + (problems.empty() ? "" : problems[0]), problems,
                     "invalid scene:");
        return static_cast<int>(EngineExit::InvalidScene);
    } catch (const OtherRunError& error) {
        return fail(EngineErrorCode::OtherRun, EngineExit::BadLibrary, error.what());
    } catch (const LibraryError& error) {
        return fail(EngineErrorCode::BadLibrary, EngineExit::BadLibrary, error.what());
    } catch (const std::exception& error) {
        return fail(EngineErrorCode::Internal, EngineExit::Failed, error.what());
    }
}

}  // namespace
}  // namespace mwb

namespace {

// Every world the engine makes holds its whole motion (every body, every frame: 30 MB for the
// staircase's 110 bodies over 40 s at 120 Hz) in a few arrays, made and dropped per world. glibc
// serves blocks that large with fresh mappings, each page faulted in and zeroed by the kernel,
// then unmapped: on a staircase search that was a seventh of the time. Kept in the heap, the
// pages are reused (a 96-world search: 54.2 s to 46.0 s in one process, 30.7 s to 28.2 s on two
// workers; the worlds are the same).
void keep_large_blocks_in_heap() {
#ifdef __GLIBC__
    constexpr int kLargeBlockBytes = 1 << 30;
    mallopt(M_MMAP_THRESHOLD, kLargeBlockBytes);
    mallopt(M_TRIM_THRESHOLD, kLargeBlockBytes);
#endif
}

}  // namespace

int main(int argc, char** argv) {
    keep_large_blocks_in_heap();
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (argc > 0) mwb::g_invoked_as = argv[0];
    auto given = [&](const char* flag) { return std::find(args.begin(), args.end(), flag) != args.end(); };
    // A worker's standard output carries its records to the supervisor, never events.
    const bool worker = !args.empty() && args[0] == "worker";
    mwb::EngineEvents events(given("--events") && !worker, given("--progress"));
    return mwb::run_reporting_failures(args, events);
}
