#pragma once
// A worker process and its two private channels, on each system the engine runs on: POSIX
// (fork, execv, pipes on descriptors 3 and 4) and Windows (CreateProcess, anonymous pipes). The
// supervisor (SupervisedSampler.cpp) and the worker (WorldWorker.cpp) see only this.
//
// Jobs go to a worker on one channel and records come back on another. Nothing else can write
// to either: the worker's standard output, where ODE and the C library print, goes to the
// engine's standard error (the log).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mwb {

/// How a worker process ended, in the words a rejection records. The same fault gives the same
/// words on every system, so a library with faulted worlds is the same file everywhere.
struct WorkerExit {
    bool normal = false;      ///< it returned from main (any exit code), not killed by a fault
    std::string description;  ///< "the simulation crashed (signal 11, Segmentation fault)"
};

class WorkerProcess {
public:
    /// Starts `engine args...` as a worker. Throws std::runtime_error naming what failed.
    WorkerProcess(const std::string& engine, const std::vector<std::string>& args);
    /// Kills the worker if it still runs, and reaps it.
    ~WorkerProcess();
    WorkerProcess(const WorkerProcess&) = delete;
    WorkerProcess& operator=(const WorkerProcess&) = delete;

    /// Sends `text` on the job channel. A worker that died shows as the end of its output, so a
    /// failed write is not an error here.
    void send(const std::string& text);
    /// True when read_some() would not block: records, or the end of the output, are waiting.
    bool output_waiting() const;
    /// Appends what the record channel holds to `into`, blocking until something comes. False
    /// once the output ended (the worker exited or died).
    bool read_some(std::vector<uint8_t>& into);
    /// Stops the worker at once (SIGKILL, TerminateProcess).
    void kill();
    /// Waits for the worker to end (after its output ended, or kill()) and says how it ended.
    WorkerExit wait();

    /// The system's handles of the process and its channels (WorkerProcess*.cpp).
    struct Handles;
    const Handles& handles() const { return *handles_; }

private:
    std::unique_ptr<Handles> handles_;
};

/// Waits until at least one of `workers` has output waiting, or `timeout_ms` passed. Returns the
/// positions in `workers` of those that have.
std::vector<size_t> wait_for_output(const std::vector<WorkerProcess*>& workers, int timeout_ms);

/// In a worker: takes its two channels before anything can print, and points its standard
/// output at standard error. Throws std::runtime_error when it was not started as a worker.
struct WorkerChannels {
    int jobs_fd = -1;     ///< read the jobs here, a line at a time
    int records_fd = -1;  ///< write the records here
};
WorkerChannels take_worker_channels();

/// The engine executable of this process, for its workers: on Linux /proc/self/exe, else
/// `invoked_as` (argv[0]) as a path or looked up on PATH as the shell did (a chroot without
/// /proc); on Windows the module's own file. Empty when it cannot be found.
std::string engine_executable(const std::string& invoked_as);

/// Makes every fatal fault in this process (abort, an access violation, a stray signal) end it
/// in a way the supervisor's WorkerExit words as on Linux, without a crash dialog or debugger.
void end_worker_quietly_on_faults();

}  // namespace mwb
