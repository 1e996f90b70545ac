#include "SupervisedSampler.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>

#include "WorldWorker.h"
#include "library/LibraryFormat.h"
#include "library/WorldRecord.h"
#include "sim/PortableRandom.h"

namespace mwb {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kFirstWorldLimit_s = 600;
constexpr double kMinWorldLimit_s = 60;
constexpr double kSlowestWorldFactor = 20;
constexpr int kPollInterval_ms = 100;

// One worker process: its pipes, the world it is on and what it has sent so far.
struct Worker {
    pid_t pid = -1;
    int to_worker = -1, from_worker = -1;
    bool busy = false;
    uint64_t world = 0;
    Clock::time_point started{};
    std::string fault;  ///< why the supervisor stopped it, if it did
    uint64_t records = 0;  ///< worlds it has sent
    std::vector<uint8_t> received;
};

std::string describe_exit(int status) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        return "the simulation crashed (signal " + std::to_string(sig) + ", " + strsignal(sig) + ")";
    }
    return "the simulation process ended unexpectedly (exit " + std::to_string(WEXITSTATUS(status)) + ")";
}

class Supervisor {
public:
    Supervisor(const SupervisedRun& run, const std::vector<uint64_t>& worlds, LibraryWriter& writer,
               const SupervisedWorldSink& on_world)
        : run_(run), worlds_(worlds), writer_(writer), on_world_(on_world) {}

    ~Supervisor() {
        for (Worker& w : workers_) stop(w);
    }

    SamplingStatistics run(const std::atomic<bool>& cancel) {
        const auto start = Clock::now();
        const size_t count = std::min<size_t>(static_cast<size_t>(std::max(1, run_.workers)), worlds_.size());
        workers_.resize(count);
        for (Worker& w : workers_) spawn(w);
        while (next_ < worlds_.size() || std::any_of(workers_.begin(), workers_.end(), [](const Worker& w) { return w.busy; })) {
            if (cancel.load()) {
                stats_.worlds_cancelled += std::count_if(workers_.begin(), workers_.end(), [](const Worker& w) { return w.busy; });
                break;
            }
            wait_for_workers();
            enforce_time_limit();
        }
        for (Worker& w : workers_) stop(w);
        stats_.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
        return stats_;
    }

private:
    void spawn(Worker& w) {
        int to[2], from[2];
        if (::pipe2(to, O_CLOEXEC) != 0 || ::pipe2(from, O_CLOEXEC) != 0)
            throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(errno));
        std::vector<char*> argv{const_cast<char*>(run_.engine_path.c_str())};
        for (const std::string& a : run_.worker_args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        const pid_t pid = ::fork();
        if (pid < 0) throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(errno));
        if (pid == 0) {
            ::dup2(to[0], STDIN_FILENO);
            ::dup2(from[1], STDOUT_FILENO);
            ::execv(argv[0], argv.data());
            std::_Exit(127);
        }
        ::close(to[0]);
        ::close(from[1]);
        w = Worker{};
        w.pid = pid;
        w.to_worker = to[1];
        w.from_worker = from[0];
        assign_next(w);
    }

    void assign_next(Worker& w) {
        if (next_ >= worlds_.size()) {
            // Nothing left: end of input lets the worker exit.
            if (w.to_worker >= 0) ::close(w.to_worker);
            w.to_worker = -1;
            return;
        }
        w.world = worlds_[next_++];
        w.busy = true;
        w.started = Clock::now();
        const std::string line = std::to_string(w.world) + "\n";
        // A worker that died already shows up as the end of its output; its world is handled there.
        [[maybe_unused]] const ssize_t written = ::write(w.to_worker, line.data(), line.size());
    }

    void wait_for_workers() {
        std::vector<pollfd> fds;
        for (const Worker& w : workers_) fds.push_back({w.from_worker, POLLIN, 0});
        if (::poll(fds.data(), fds.size(), kPollInterval_ms) <= 0) return;
        for (size_t k = 0; k < workers_.size(); ++k)
            if (fds[k].revents & (POLLIN | POLLHUP | POLLERR)) read_from(workers_[k]);
    }

    void read_from(Worker& w) {
        uint8_t chunk[1 << 16];
        const ssize_t n = ::read(w.from_worker, chunk, sizeof chunk);
        if (n < 0 && errno == EINTR) return;
        if (n <= 0) return worker_ended(w);
        w.received.insert(w.received.end(), chunk, chunk + n);
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
        writer_.append_record(h.type, h.version, payload);
        std::string reason;
        if (h.type == kRecordTypeRejection) {
            reason = decode_rejection_record(payload.data(), payload.size(), "worker").reason;
            ++stats_.worlds_rejected;
            ++stats_.reject_reasons[reason];
        } else {
            ++stats_.worlds_ok;
        }
        slowest_s_ = std::max(slowest_s_, std::chrono::duration<double>(Clock::now() - w.started).count());
        w.busy = false;
        ++w.records;
        if (on_world_) on_world_(h.world_index, h.type == kRecordTypeWorld, reason);
        assign_next(w);
    }

    // The worker's output ended: it exited after its input did, or it died in a world.
    void worker_ended(Worker& w) {
        int status = 0;
        ::waitpid(w.pid, &status, 0);
        ::close(w.from_worker);
        if (w.to_worker >= 0) ::close(w.to_worker);
        w.pid = w.from_worker = w.to_worker = -1;
        if (!w.busy) return;
        // A worker that stops normally without a single world could not start at all (no scene,
        // no engine): every world would fail the same way, so the run stops here.
        if (w.fault.empty() && WIFEXITED(status) && w.records == 0)
            throw std::runtime_error("a simulation worker could not start (" + describe_exit(status) + ")");
        reject(w.world, w.fault.empty() ? describe_exit(status) : w.fault);
        if (next_ < worlds_.size()) spawn(w);
        else w.busy = false;
    }

    void reject(uint64_t world_index, const std::string& reason) {
        WorldResult world;
        world.world_index = world_index;
        world.seed = derive_world_seed(run_.base_seed, world_index);
        world.status = WorldStatus::Rejected;
        world.reject_reason = reason;
        writer_.append(world);
        ++stats_.worlds_rejected;
        ++stats_.reject_reasons[reason];
        if (on_world_) on_world_(world_index, false, reason);
    }

    double time_limit_s() const {
        if (run_.world_time_limit_s > 0) return run_.world_time_limit_s;
        return slowest_s_ > 0 ? std::max(kMinWorldLimit_s, kSlowestWorldFactor * slowest_s_) : kFirstWorldLimit_s;
    }

    void enforce_time_limit() {
        const double limit = time_limit_s();
        for (Worker& w : workers_) {
            if (!w.busy || w.pid < 0 || !w.fault.empty()) continue;
            if (std::chrono::duration<double>(Clock::now() - w.started).count() <= limit) continue;
            w.fault = "the simulation did not finish within " + std::to_string(static_cast<long>(limit)) + " s";
            ::kill(w.pid, SIGKILL);
        }
    }

    void stop(Worker& w) {
        if (w.pid < 0) return;
        if (w.to_worker >= 0) ::close(w.to_worker);
        ::kill(w.pid, SIGKILL);
        ::waitpid(w.pid, nullptr, 0);
        ::close(w.from_worker);
        w.pid = w.from_worker = w.to_worker = -1;
    }

    const SupervisedRun& run_;
    const std::vector<uint64_t>& worlds_;
    LibraryWriter& writer_;
    const SupervisedWorldSink& on_world_;
    std::vector<Worker> workers_;
    size_t next_ = 0;
    double slowest_s_ = 0;
    SamplingStatistics stats_;
};

}  // namespace

SamplingStatistics sample_supervised(const SupervisedRun& run, const std::vector<uint64_t>& worlds,
                                     LibraryWriter& writer, const SupervisedWorldSink& on_world,
                                     const std::atomic<bool>& cancel) {
    if (worlds.empty()) return {};
    // A worker that dies leaves a broken pipe; that must not end the supervisor.
    ::signal(SIGPIPE, SIG_IGN);
    Supervisor supervisor(run, worlds, writer, on_world);
    return supervisor.run(cancel);
}

}  // namespace mwb
