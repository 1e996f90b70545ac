#include "WorldWorker.h"

#ifdef _WIN32
#include <io.h>
#else
#include <unistd.h>
#endif

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include "WorkerJob.h"
#include "WorkerProcess.h"
#include "library/LibraryFormat.h"
#include "library/LibraryReader.h"
#include "library/WorldRecordEncoder.h"
#include "refine/LineageCache.h"
#include "refine/RefineError.h"
#include "scene/SceneJson.h"
#include "sim/OdeMessages.h"
#include "sim/OdeWorld.h"
#include "sim/SharedPrefix.h"
#include "sim/WorldSimulator.h"

namespace mwb {
namespace {

// Test-only: MWB_ENGINE_TEST_FAULTS="3:abort,5:segv,7:hang,9:print,2:slow,4:odemessage" makes those
// worlds fail the way a broken ODE can (or print as ODE does, finish late, or give ODE a message), so tests can check that a run survives them. Never set
// in production.
std::map<uint64_t, std::string> injected_faults() {
    std::map<uint64_t, std::string> faults;
    const char* spec = std::getenv("MWB_ENGINE_TEST_FAULTS");
    if (!spec) return faults;
    std::string text = spec;
    size_t start = 0;
    while (start < text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        const size_t colon = item.find(':');
        if (colon != std::string::npos) faults[std::stoull(item.substr(0, colon))] = item.substr(colon + 1);
        start = comma + 1;
    }
    return faults;
}

void fail_as_injected(const std::string& fault) {
    if (fault == "abort") std::abort();
    // A message from ODE while the world steps, through ODE's own handler: it must become one
    // warning naming the world.
    if (fault == "odemessage") return;
    // Finishing late, so that later worlds finish first: records must still come in world order.
    if (fault == "slow") {
        std::this_thread::sleep_for(std::chrono::milliseconds(500));
        return;
    }
    // Text where a careless library would put it, mid-run: it must reach the log, not a record.
    if (fault == "print") {
        std::printf("WARNING: Polygon 0 is not defined counterclockwise\n");
        std::fflush(stdout);
        std::fprintf(stderr, "a library's message on standard error\n");
        return;
    }
    if (fault == "segv") std::raise(SIGSEGV);
    if (fault == "hang")
        for (;;) std::this_thread::sleep_for(std::chrono::hours(1));
}

// The "odemessage" fault: ODE's own message function called as quickstep calls it, half a second
// into the world, through the handler the engine installs.
WorldResult with_injected_messages(WorldResult world, const std::string& fault) {
    if (fault == "odemessage") {
        OdeMessageCapture capture(world.ode_messages, 0.5);
        dMessage(d_ERR_LCP, "LCP internal error, s <= 0 (s=%.4e)", -1.5e-5);
    }
    return world;
}

// The worker's two channels (WorkerProcess.h), taken once as it starts.
WorkerChannels g_channels;

void write_all(const uint8_t* data, size_t size) {
    while (size > 0) {
        const auto n = ::write(g_channels.records_fd, data, static_cast<unsigned>(std::min<size_t>(size, 1u << 30)));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) std::_Exit(3);  // the supervisor is gone: nothing left to do
        data += n;
        size -= static_cast<size_t>(n);
    }
}

void put_u32(uint8_t* out, uint32_t v) { std::memcpy(out, &v, 4); }

// The jobs the supervisor sends, a line at a time.
class JobLines {
public:
    bool next(std::string& line) {
        for (;;) {
            const size_t end = pending_.find('\n');
            if (end != std::string::npos) {
                line = pending_.substr(0, end);
                pending_.erase(0, end + 1);
                return true;
            }
            char chunk[4096];
            const auto n = ::read(g_channels.jobs_fd, chunk, sizeof chunk);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return false;  // the supervisor closed the channel: no more jobs
            pending_.append(chunk, static_cast<size_t>(n));
        }
    }

private:
    std::string pending_;
};

void send_record(uint64_t world_index, uint32_t type, uint32_t version, const std::vector<uint8_t>& payload) {
    uint8_t header[kWorkerRecordHeaderBytes];
    std::memcpy(header, &world_index, 8);
    put_u32(header + 8, type);
    put_u32(header + 12, version);
    put_u32(header + 16, static_cast<uint32_t>(payload.size()));
    write_all(header, sizeof header);
    write_all(payload.data(), payload.size());
}

void send_world(const WorldResult& world, const CodecBounds& bounds, const Vec3& gravity) {
    if (!world.ode_messages.empty()) {
        const std::string text = encode_ode_messages(world.ode_messages);
        send_record(world.world_index, kWorkerOdeMessages, 0, std::vector<uint8_t>(text.begin(), text.end()));
    }
    if (world.status == WorldStatus::Ok)
        send_record(world.world_index, kRecordTypeWorld, kWorldRecordVersion, encode_world_record(world, bounds, gravity));
    else if (world.status == WorldStatus::Rejected)
        send_record(world.world_index, kRecordTypeRejection, kRejectionRecordVersion, encode_rejection_record(world));
}

// Lineages the workers of one run keep between them (a search refines the children it made again
// and again), each a share by the number of workers (--threads), but never less than the least.
constexpr size_t kWorkersLineageBytes = size_t{1536} << 20;
constexpr size_t kLeastWorkerLineageBytes = size_t{256} << 20;

void refuse(uint64_t world_index, WorkerRefusal why, const std::string& message) {
    send_record(world_index, kWorkerRefusal, static_cast<uint32_t>(why), std::vector<uint8_t>(message.begin(), message.end()));
}

// What a library's worker needs of it: read once, then the reader (every world's tracks) is let go.
struct LibraryRun {
    RunHeader header;
    std::string scene_json;
    bool revised = false;
};

LibraryRun read_library_run(const std::string& path) {
    const LibraryReader reader(path);
    return {reader.header(), reader.scene_json(), reader.scene_revision() > 0};
}

// A library's run: sampled worlds in the scene as sampled, refined children in the scene now.
int run_library_worker(const EngineOptions& options, const std::map<uint64_t, std::string>& faults) {
    const LibraryRun run = read_library_run(options.library_path);
    const RunHeader& header = run.header;
    Scene sampled_scene = scene_from_json(header.scene_json);
    const size_t sampled_bodies = sampled_scene.bodies.size();
    const Vec3 gravity = sampled_scene.world.gravity;
    const CompiledScene sampled(std::move(sampled_scene), header.parameters);
    // Bodies added by refinements since sampling (a scene revision) are in refined children only.
    std::optional<CompiledScene> revised;
    if (run.revised) revised.emplace(scene_from_json(run.scene_json), header.parameters, sampled_bodies);
    const CompiledScene& scene_now = revised ? *revised : sampled;
    initialize_ode_once();
    PrefixSharingSimulator simulator(sampled, header.base_seed, true);
    const size_t workers = options.threads > 0 ? static_cast<size_t>(options.threads) : 1;
    LineageCache kept(std::max(kLeastWorkerLineageBytes, kWorkersLineageBytes / workers));
    // The lineage of the parent whose children came last, and whether it was made in a changed
    // scene: a refinement's children come one job each, mostly in a row, and share it rather than
    // each copying it out of `kept` (a copy of a SIGGRAPH lineage per child was 3% of a search's
    // time). A refinement that changes the scene cannot use kept worlds.
    struct SharedLineage {
        uint64_t parent_world;
        bool scene_changed;
        std::vector<WorldResult> chain;
    };
    std::optional<SharedLineage> lineage;
    JobLines jobs;
    std::string line;
    while (jobs.next(line)) {
        const WorkerJob job = parse_worker_line(line);
        const auto fault = faults.find(job.world_index);
        if (!job.refined) {
            if (fault != faults.end()) fail_as_injected(fault->second);
            WorldResult world = simulator.simulate(job.world_index);
            send_world(world, header.bounds, gravity);
            kept.keep(std::move(world));
            continue;
        }
        const RefinementJob& refinement = job.refinement;
        try {
            if (!lineage || lineage->parent_world != refinement.parent_world ||
                lineage->scene_changed != refinement.scene_changed)
                lineage = SharedLineage{refinement.parent_world, refinement.scene_changed,
                                        exact_lineage(scene_now, header.base_seed, refinement,
                                                      refinement.scene_changed ? nullptr : &kept)};
        } catch (const WorldNotReproduced& refused) {
            refuse(job.world_index, WorkerRefusal::NotReproduced, refused.what());
            continue;
        }
        send_record(job.world_index, kWorkerLineageReady, 0, {});
        // An injected fault strikes the child's own simulation, as a broken ODE would.
        if (fault != faults.end()) fail_as_injected(fault->second);
        WorldResult child;
        try {
            child = refine_world(scene_now, header.base_seed, lineage->chain, refinement.children.front());
        } catch (const std::invalid_argument& misfit) {
            refuse(job.world_index, WorkerRefusal::DoesNotFit, misfit.what());
            continue;
        }
        send_world(child, header.bounds, gravity);
        if (!refinement.scene_changed) kept.keep(std::move(child));
    }
    return 0;
}

}  // namespace

int run_world_worker(const EngineOptions& options) {
    // Ctrl-C reaches the whole process group; cancelling is the supervisor's decision.
    std::signal(SIGINT, SIG_IGN);
    g_channels = take_worker_channels();
    end_worker_quietly_on_faults();
    const std::map<uint64_t, std::string> faults = injected_faults();
    if (!options.library_path.empty()) return run_library_worker(options, faults);
    const Scene scene = load_scene_file(options.scene_path);
    const Vec3 gravity = scene.world.gravity;
    const CompiledScene compiled(scene, options.parameters);
    initialize_ode_once();
    // A worker lives for many worlds: the later ones share the first one's prefix.
    PrefixSharingSimulator simulator(compiled, options.base_seed, options.share_prefix);
    JobLines jobs;
    std::string line;
    while (jobs.next(line)) {
        const WorkerJob job = parse_worker_line(line);
        const auto fault = faults.find(job.world_index);
        if (fault != faults.end()) fail_as_injected(fault->second);
        WorldResult world = simulator.simulate(job.world_index);
        if (fault != faults.end()) world = with_injected_messages(std::move(world), fault->second);
        send_world(world, options.bounds, gravity);
    }
    return 0;
}

}  // namespace mwb
