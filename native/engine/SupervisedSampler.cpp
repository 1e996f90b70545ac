#include "SupervisedSampler.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "WorkerJob.h"
#include "WorkerProcess.h"
#include "WorldWorker.h"
#include "library/LibraryFormat.h"
#include "library/WorldRecord.h"
#include "sampler/InOrderDelivery.h"
#include "sim/OdeMessages.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kFirstWorldLimit_s = 600;
constexpr double kMinWorldLimit_s = 60;
constexpr double kSlowestWorldFactor = 20;
constexpr int kPollInterval_ms = 100;

// One worker process: the world it is on and what it has sent so far.
struct Worker {
    std::unique_ptr<WorkerProcess> process;  ///< none until started, and after it ended
    bool busy = false;
    size_t task = 0;     ///< the position of its task in the run, while busy
    uint64_t world = 0;  ///< the world it is on, while busy
    uint32_t lineage_worlds = 0;  ///< its task's (WorkerTask)
    bool lineage_ready = true;    ///< it has the task's lineage: `started` is the world's own start
    Clock::time_point started{};
    std::string fault;  ///< why the supervisor stopped it, if it did
    uint64_t records = 0;  ///< worlds it has sent
    std::vector<uint8_t> received;
};

// A world's outcome waiting in the reorder window: a worker's record, or the rejection the
// supervisor writes for a world whose worker died.
struct HeldRecord {
    uint32_t type = 0, version = 0;
    std::vector<uint8_t> payload;
    std::optional<WorldResult> rejection;
};

}  // namespace

class WorkerPool::Supervisor {
public:
    explicit Supervisor(SupervisedRun run) : run_(std::move(run)) {}

    ~Supervisor() {
        for (Worker& w : workers_) stop(w);
    }

    SamplingStatistics run(const std::vector<WorkerTask>& tasks, LibraryWriter& writer,
                           const SupervisedWorldSink& on_world, const std::atomic<bool>& cancel) {
        const auto start = Clock::now();
        tasks_ = &tasks;
        on_world_ = &on_world;
        next_ = 0;
        stats_ = {};
        refusal_ = {};
        InOrderDelivery<HeldRecord> in_order([&](HeldRecord&& record) {
            if (record.rejection) writer.append(*record.rejection);
            else writer.append_record(record.type, record.version, record.payload);
        });
        in_order_ = &in_order;
        try {
            run_tasks(cancel);
        } catch (...) {
            // Every world already made is kept, whatever ends the run.
            in_order.flush();
            in_order_ = nullptr;
            throw;
        }
        in_order.flush();
        in_order_ = nullptr;
        stats_.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
        tasks_ = nullptr;
        return stats_;
    }

    const Refusal& refusal() const { return refusal_; }

private:
    void run_tasks(const std::atomic<bool>& cancel) {
        reap_idle_workers();
        const size_t wanted = std::min<size_t>(static_cast<size_t>(std::max(1, run_.workers)), tasks_->size());
        if (workers_.size() < wanted) workers_.resize(wanted);
        for (Worker& w : workers_) {
            if (next_ >= tasks_->size()) break;
            if (!w.process) spawn(w);
            assign_next(w);
        }
        while (next_ < tasks_->size() || any_busy()) {
            if (cancel.load()) {
                stats_.worlds_cancelled += std::count_if(workers_.begin(), workers_.end(), [](const Worker& w) { return w.busy; });
                for (Worker& w : workers_) stop(w);
                return;
            }
            wait_for_workers();
            enforce_time_limit();
        }
    }

    // A worker stopped for a hang, or one that died while idle (its output ended), is not handed
    // a task: the world given to it would be blamed for its end.
    void reap_idle_workers() {
        for (Worker& w : workers_) {
            if (!w.process) continue;
            if (!w.fault.empty() || w.process->output_waiting()) stop(w);
        }
    }

    bool any_busy() const {
        return std::any_of(workers_.begin(), workers_.end(), [](const Worker& w) { return w.busy; });
    }

    void spawn(Worker& w) {
        w = Worker{};
        w.process = std::make_unique<WorkerProcess>(run_.engine_path, run_.worker_args);
    }

    // Hands the worker the next task, if any; an idle worker waits for the next run.
    void assign_next(Worker& w) {
        if (next_ >= tasks_->size()) return;
        w.task = next_;
        const WorkerTask& task = (*tasks_)[next_++];
        w.world = task.world_index;
        w.busy = true;
        w.lineage_worlds = task.lineage_worlds;
        w.lineage_ready = task.lineage_worlds == 0;
        w.started = Clock::now();
        // A worker that died already shows up as the end of its output; its world is handled there.
        w.process->send(task.line + "\n");
    }

    void wait_for_workers() {
        std::vector<WorkerProcess*> running;
        std::vector<Worker*> polled;
        for (Worker& w : workers_)
            if (w.process) {
                running.push_back(w.process.get());
                polled.push_back(&w);
            }
        for (size_t k : wait_for_output(running, kPollInterval_ms)) read_from(*polled[k]);
    }

    void read_from(Worker& w) {
        if (!w.process->read_some(w.received)) return worker_ended(w);
        while (w.received.size() >= kWorkerRecordHeaderBytes) {
            WorkerRecordHeader h;
            std::memcpy(&h.world_index, w.received.data(), 8);
            std::memcpy(&h.type, w.received.data() + 8, 4);
            std::memcpy(&h.version, w.received.data() + 12, 4);
            std::memcpy(&h.size, w.received.data() + 16, 4);
            if (w.received.size() < kWorkerRecordHeaderBytes + h.size) return;
            const auto payload_begin = w.received.begin() + kWorkerRecordHeaderBytes;
            const std::vector<uint8_t> payload(payload_begin, payload_begin + h.size);
            w.received.erase(w.received.begin(), payload_begin + h.size);
            store(w, h, payload);
        }
    }

    void store(Worker& w, const WorkerRecordHeader& h, const std::vector<uint8_t>& payload) {
        if (h.type == kWorkerOdeMessages) {
            note_ode_messages(stats_.ode_messages, h.world_index,
                              decode_ode_messages(std::string(payload.begin(), payload.end())));
            return;
        }
        if (h.type == kWorkerLineageReady) {
            w.lineage_ready = true;
            w.started = Clock::now();
            return;
        }
        w.busy = false;
        ++w.records;
        if (h.type == kWorkerRefusal) {
            // Every later task of the run would be refused alike (they refine the same world).
            refusal_ = {h.version == static_cast<uint32_t>(WorkerRefusal::NotReproduced),
                        std::string(payload.begin(), payload.end())};
            next_ = tasks_->size();
            in_order_->skip(w.task);
            return;
        }
        std::string reason;
        if (h.type == kRecordTypeRejection) {
            reason = decode_rejection_record(payload.data(), payload.size(), "worker").reason;
            ++stats_.worlds_rejected;
            ++stats_.reject_reasons[reason];
        } else {
            ++stats_.worlds_ok;
        }
        slowest_s_ = std::max(slowest_s_, std::chrono::duration<double>(Clock::now() - w.started).count());
        in_order_->arrive(w.task, {h.type, h.version, payload, std::nullopt});
        if (*on_world_) (*on_world_)(h.world_index, h.type == kRecordTypeWorld, reason);
        // A worker stopped for a hang just as it finished is not handed another world.
        if (w.fault.empty()) assign_next(w);
    }

    // The worker's output ended: it died in a world (or, idle, for no reason of its own).
    void worker_ended(Worker& w) {
        const WorkerExit exit = w.process->wait();
        w.process.reset();
        if (w.busy) {
            w.busy = false;
            // A worker that stops normally without a single world could not start at all (no
            // scene, no library, no engine): every world would fail the same way, so the run stops.
            if (w.fault.empty() && exit.normal && w.records == 0)
                throw std::runtime_error("a simulation worker could not start (" + exit.description + ")");
            reject(w.task, w.world, w.fault.empty() ? exit.description : w.fault);
        }
        if (next_ < tasks_->size()) {
            spawn(w);
            assign_next(w);
        }
    }

    void reject(size_t task, uint64_t world_index, const std::string& reason) {
        WorldResult world;
        world.world_index = world_index;
        world.seed = derive_world_seed(run_.base_seed, world_index);
        world.status = WorldStatus::Rejected;
        world.reject_reason = reason;
        in_order_->arrive(task, {0, 0, {}, std::move(world)});
        ++stats_.worlds_rejected;
        ++stats_.reject_reasons[reason];
        if (*on_world_) (*on_world_)(world_index, false, reason);
    }

    double time_limit_s() const {
        if (run_.world_time_limit_s > 0) return run_.world_time_limit_s;
        return slowest_s_ > 0 ? std::max(kMinWorldLimit_s, kSlowestWorldFactor * slowest_s_) : kFirstWorldLimit_s;
    }

    void enforce_time_limit() {
        const double limit = time_limit_s();
        for (Worker& w : workers_) {
            if (!w.busy || !w.process || !w.fault.empty()) continue;
            // Re-simulating a lineage first takes up to as long as its worlds.
            const double allowed = w.lineage_ready ? limit : limit * (1.0 + w.lineage_worlds);
            if (std::chrono::duration<double>(Clock::now() - w.started).count() <= allowed) continue;
            w.fault = "the simulation did not finish within " + std::to_string(static_cast<long>(allowed)) + " s";
            w.process->kill();
        }
    }

    // Ends the worker at once (its process is killed and reaped) and forgets it.
    void stop(Worker& w) { w = Worker{}; }

    SupervisedRun run_;
    std::vector<Worker> workers_;
    double slowest_s_ = 0;
    // The run under way.
    const std::vector<WorkerTask>* tasks_ = nullptr;
    InOrderDelivery<HeldRecord>* in_order_ = nullptr;  ///< records wait here to be written in task order
    const SupervisedWorldSink* on_world_ = nullptr;
    size_t next_ = 0;
    SamplingStatistics stats_;
    Refusal refusal_;
};

WorkerPool::WorkerPool(SupervisedRun run) : supervisor_(std::make_unique<Supervisor>(std::move(run))) {}

WorkerPool::~WorkerPool() = default;

SamplingStatistics WorkerPool::run(const std::vector<WorkerTask>& tasks, LibraryWriter& writer,
                                   const SupervisedWorldSink& on_world, const std::atomic<bool>& cancel) {
    return supervisor_->run(tasks, writer, on_world, cancel);
}

const WorkerPool::Refusal& WorkerPool::refusal() const { return supervisor_->refusal(); }

namespace {

std::vector<WorkerTask> sampling_tasks(const std::vector<uint64_t>& worlds) {
    std::vector<WorkerTask> tasks;
    for (uint64_t w : worlds) tasks.push_back({w, sampled_world_line(w)});
    return tasks;
}

}  // namespace

SamplingStatistics sample_supervised(const SupervisedRun& run, const std::vector<uint64_t>& worlds,
                                     LibraryWriter& writer, const SupervisedWorldSink& on_world,
                                     const std::atomic<bool>& cancel) {
    if (worlds.empty()) return {};
    WorkerPool pool(run);
    return pool.run(sampling_tasks(worlds), writer, on_world, cancel);
}

const std::atomic<bool>& SupervisedWorlds::cancel_of(const SamplingProgress* progress) const {
    return progress ? progress->cancel : never_cancelled_;
}

SamplingStatistics SupervisedWorlds::sample(const CompiledScene&, uint64_t, const std::vector<uint64_t>& indices,
                                            LibraryWriter& writer, const MadeWorldSink& on_world,
                                            SamplingProgress* progress) {
    return pool_.run(sampling_tasks(indices), writer, on_world, cancel_of(progress));
}

SamplingStatistics SupervisedWorlds::refine(const CompiledScene&, uint64_t, const RefinementJob& job,
                                            LibraryWriter& writer, const MadeWorldSink& on_world,
                                            SamplingProgress* progress) {
    std::vector<WorkerTask> tasks;
    const auto lineage_worlds = static_cast<uint32_t>(job.lineage.size() + 1);
    for (size_t k = 0; k < job.children.size(); ++k)
        tasks.push_back({job.children[k].world_index, refined_child_line(job, k), lineage_worlds});
    const SamplingStatistics stats = pool_.run(tasks, writer, on_world, cancel_of(progress));
    // Every child of the job has the same parent: a refusal is every worker's.
    const WorkerPool::Refusal& refused = pool_.refusal();
    if (!refused.message.empty()) {
        if (refused.not_reproduced) throw WorldNotReproduced(refused.message);
        throw RefineError(refused.message);
    }
    return stats;
}

}  // namespace mwb
