// WorkerProcess on POSIX systems: fork and execv, the channels on descriptors 3 and 4.
#include "WorkerProcess.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace mwb {
namespace {

// The descriptors a worker is handed: jobs come in on one, records go out on the other.
constexpr int kJobsFd = 3;
constexpr int kRecordsFd = 4;

std::string describe_exit(int status) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        return "the simulation crashed (signal " + std::to_string(sig) + ", " + strsignal(sig) + ")";
    }
    return "the simulation process ended unexpectedly (exit " + std::to_string(WEXITSTATUS(status)) + ")";
}

bool is_executable_file(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

}  // namespace

struct WorkerProcess::Handles {
    pid_t pid = -1;
    int to_worker = -1, from_worker = -1;
    bool reaped = false;
    int status = 0;
};

WorkerProcess::WorkerProcess(const std::string& engine, const std::vector<std::string>& args)
    : handles_(std::make_unique<Handles>()) {
    // A worker that dies leaves a broken pipe; writing to it must not end the supervisor.
    ::signal(SIGPIPE, SIG_IGN);
    int to[2] = {-1, -1}, from[2] = {-1, -1};
    auto fail = [&](const char* what) {
        const std::string message = std::string("cannot start a worker: ") + what + ": " + std::strerror(errno);
        for (int fd : {to[0], to[1], from[0], from[1]})
            if (fd >= 0) ::close(fd);
        throw std::runtime_error(message);
    };
    if (::pipe2(to, O_CLOEXEC) != 0 || ::pipe2(from, O_CLOEXEC) != 0) fail("pipe");
    std::vector<char*> argv{const_cast<char*>(engine.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) fail("fork");
    if (pid == 0) {
        // Jobs and records travel on descriptors of their own. ODE and the C library print to
        // standard output: in a worker that is the engine's standard error, the log.
        const int jobs = ::fcntl(to[0], F_DUPFD, kRecordsFd + 1);
        const int records = ::fcntl(from[1], F_DUPFD, kRecordsFd + 1);
        const int nothing = ::open("/dev/null", O_RDONLY);
        if (jobs < 0 || records < 0 || nothing < 0 || ::dup2(jobs, kJobsFd) < 0 || ::dup2(records, kRecordsFd) < 0 ||
            ::dup2(nothing, STDIN_FILENO) < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0)
            std::_Exit(127);
        ::execv(argv[0], argv.data());
        std::_Exit(127);
    }
    ::close(to[0]);
    ::close(from[1]);
    handles_->pid = pid;
    handles_->to_worker = to[1];
    handles_->from_worker = from[0];
}

WorkerProcess::~WorkerProcess() {
    if (handles_->to_worker >= 0) ::close(handles_->to_worker);
    if (!handles_->reaped) {
        ::kill(handles_->pid, SIGKILL);
        ::waitpid(handles_->pid, nullptr, 0);
    }
    ::close(handles_->from_worker);
}

void WorkerProcess::send(const std::string& text) {
    [[maybe_unused]] const ssize_t written = ::write(handles_->to_worker, text.data(), text.size());
}

bool WorkerProcess::output_waiting() const {
    pollfd fd{handles_->from_worker, POLLIN, 0};
    return ::poll(&fd, 1, 0) > 0;
}

bool WorkerProcess::read_some(std::vector<uint8_t>& into) {
    uint8_t chunk[1 << 16];
    const ssize_t n = ::read(handles_->from_worker, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) return true;
    if (n <= 0) return false;
    into.insert(into.end(), chunk, chunk + n);
    return true;
}

void WorkerProcess::kill() { ::kill(handles_->pid, SIGKILL); }

WorkerExit WorkerProcess::wait() {
    if (!handles_->reaped) {
        ::waitpid(handles_->pid, &handles_->status, 0);
        handles_->reaped = true;
    }
    return {WIFEXITED(handles_->status), describe_exit(handles_->status)};
}

std::vector<size_t> wait_for_output(const std::vector<WorkerProcess*>& workers, int timeout_ms) {
    std::vector<pollfd> fds;
    for (const WorkerProcess* w : workers) fds.push_back({w->handles().from_worker, POLLIN, 0});
    std::vector<size_t> ready;
    if (fds.empty() || ::poll(fds.data(), fds.size(), timeout_ms) <= 0) return ready;
    for (size_t k = 0; k < fds.size(); ++k)
        if (fds[k].revents & (POLLIN | POLLHUP | POLLERR)) ready.push_back(k);
    return ready;
}

WorkerChannels take_worker_channels() {
    if (::fcntl(kJobsFd, F_GETFD) < 0 || ::fcntl(kRecordsFd, F_GETFD) < 0)
        throw std::runtime_error("a worker runs only under the engine's supervisor (no job channel)");
    return {kJobsFd, kRecordsFd};
}

void end_worker_quietly_on_faults() {
    // A fault ends the process by its signal, which the supervisor's waitpid reads.
}

std::string engine_executable(const std::string& invoked_as) {
    char path[4096];
    const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
    if (n > 0) return std::string(path, static_cast<size_t>(n));
    if (invoked_as.find('/') != std::string::npos) return is_executable_file(invoked_as) ? invoked_as : std::string();
    const char* search = std::getenv("PATH");
    std::istringstream dirs(search ? search : "");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        const std::string candidate = (dir.empty() ? "." : dir) + "/" + invoked_as;
        if (!invoked_as.empty() && is_executable_file(candidate)) return candidate;
    }
    return {};
}

}  // namespace mwb
