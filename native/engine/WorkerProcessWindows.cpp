// WorkerProcess on Windows: CreateProcess with anonymous pipes. The worker's standard input is
// its job channel and its standard output the record channel, for the moment it takes them
// (take_worker_channels): then its standard output becomes the engine's standard error, where
// ODE's prints belong, before any world is simulated.
#include "WorkerProcess.h"

#ifndef NOMINMAX
#define NOMINMAX
#endif
#include <windows.h>

#include <fcntl.h>
#include <io.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <stdexcept>
#include <thread>

namespace mwb {
namespace {

// A worker ended by a fault exits with this plus the POSIX number of the signal the fault is on
// Linux (11 for an access violation), so the supervisor words it as on Linux.
constexpr DWORD kFaultExitBase = 0xE0DE0000u;
// The exit code of a worker the supervisor stopped.
constexpr UINT kKilledExit = 0xE0DE0009u;

constexpr int kSigIll = 4, kSigAbrt = 6, kSigFpe = 8, kSigSegv = 11;

// glibc's strsignal words, so a rejection reads (and is stored) the same on every system.
const char* signal_words(int sig) {
    switch (sig) {
        case kSigIll: return "Illegal instruction";
        case kSigAbrt: return "Aborted";
        case kSigFpe: return "Floating point exception";
        case 9: return "Killed";
        case kSigSegv: return "Segmentation fault";
        default: return "Unknown signal";
    }
}

WorkerExit describe_exit(DWORD code) {
    if ((code & 0xFFFF0000u) == kFaultExitBase) {
        const int sig = static_cast<int>(code & 0xFFFFu);
        return {false, "the simulation crashed (signal " + std::to_string(sig) + ", " + signal_words(sig) + ")"};
    }
    if (code >= 0xC0000000u) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%08lX", static_cast<unsigned long>(code));
        return {false, std::string("the simulation crashed (exception ") + hex + ")"};
    }
    return {true, "the simulation process ended unexpectedly (exit " + std::to_string(code) + ")"};
}

std::wstring wide(const std::string& utf8) {
    if (utf8.empty()) return {};
    const int n = MultiByteToWideChar(CP_UTF8, 0, utf8.data(), static_cast<int>(utf8.size()), nullptr, 0);
    std::wstring out(static_cast<size_t>(n), L'\0');
    MultiByteToWideChar(CP_UTF8, 0, utf8.data(), static_cast<int>(utf8.size()), out.data(), n);
    return out;
}

std::string utf8(const std::wstring& text) {
    if (text.empty()) return {};
    const int n = WideCharToMultiByte(CP_UTF8, 0, text.data(), static_cast<int>(text.size()), nullptr, 0, nullptr, nullptr);
    std::string out(static_cast<size_t>(n), '\0');
    WideCharToMultiByte(CP_UTF8, 0, text.data(), static_cast<int>(text.size()), out.data(), n, nullptr, nullptr);
    return out;
}

// One argument as the C runtime's command-line parser reads it back: quoted when it has spaces,
// tabs or quotes, with backslashes doubled only before a quote.
std::wstring quoted(const std::wstring& arg) {
    if (!arg.empty() && arg.find_first_of(L" \t\"") == std::wstring::npos) return arg;
    std::wstring out = L"\"";
    size_t backslashes = 0;
    for (wchar_t c : arg) {
        if (c == L'\\') {
            ++backslashes;
            continue;
        }
        out.append(c == L'"' ? 2 * backslashes + 1 : backslashes, L'\\');
        backslashes = 0;
        out += c;
    }
    out.append(2 * backslashes, L'\\');
    return out + L"\"";
}

[[noreturn]] void fail(const char* what) {
    throw std::runtime_error(std::string("cannot start a worker: ") + what + " (Windows error " +
                             std::to_string(GetLastError()) + ")");
}

void close(HANDLE& h) {
    if (h != nullptr && h != INVALID_HANDLE_VALUE) CloseHandle(h);
    h = nullptr;
}

}  // namespace

struct WorkerProcess::Handles {
    HANDLE process = nullptr;
    HANDLE to_worker = nullptr, from_worker = nullptr;
    bool waited = false;
    DWORD exit_code = 0;
};

WorkerProcess::WorkerProcess(const std::string& engine, const std::vector<std::string>& args)
    : handles_(std::make_unique<Handles>()) {
    SECURITY_ATTRIBUTES inherited{sizeof(SECURITY_ATTRIBUTES), nullptr, TRUE};
    HANDLE jobs_read = nullptr, jobs_write = nullptr, records_read = nullptr, records_write = nullptr, log = nullptr;
    auto close_all = [&] {
        for (HANDLE* h : {&jobs_read, &jobs_write, &records_read, &records_write, &log}) close(*h);
    };
    try {
        // Only the worker's ends are inherited.
        if (!CreatePipe(&jobs_read, &jobs_write, &inherited, 0) || !SetHandleInformation(jobs_write, HANDLE_FLAG_INHERIT, 0))
            fail("a pipe for its jobs");
        if (!CreatePipe(&records_read, &records_write, &inherited, 0) ||
            !SetHandleInformation(records_read, HANDLE_FLAG_INHERIT, 0))
            fail("a pipe for its records");
        const HANDLE own_log = GetStdHandle(STD_ERROR_HANDLE);
        if (own_log == nullptr || own_log == INVALID_HANDLE_VALUE ||
            !DuplicateHandle(GetCurrentProcess(), own_log, GetCurrentProcess(), &log, 0, TRUE, DUPLICATE_SAME_ACCESS))
            log = CreateFileW(L"NUL", GENERIC_WRITE, FILE_SHARE_READ | FILE_SHARE_WRITE, &inherited, OPEN_EXISTING, 0, nullptr);
        if (log == INVALID_HANDLE_VALUE) fail("its log");

        // The worker inherits its three handles and no other (the engine's event pipe stays ours).
        HANDLE passed[3] = {jobs_read, records_write, log};
        SIZE_T list_bytes = 0;
        InitializeProcThreadAttributeList(nullptr, 1, 0, &list_bytes);
        std::vector<char> list_memory(list_bytes);
        auto* list = reinterpret_cast<LPPROC_THREAD_ATTRIBUTE_LIST>(list_memory.data());
        const bool listed = list_bytes > 0 && InitializeProcThreadAttributeList(list, 1, 0, &list_bytes) &&
                            UpdateProcThreadAttribute(list, 0, PROC_THREAD_ATTRIBUTE_HANDLE_LIST, passed, sizeof passed,
                                                      nullptr, nullptr);
        STARTUPINFOEXW start{};
        start.StartupInfo.cb = listed ? sizeof(STARTUPINFOEXW) : sizeof(STARTUPINFOW);
        start.StartupInfo.dwFlags = STARTF_USESTDHANDLES;
        start.StartupInfo.hStdInput = jobs_read;
        start.StartupInfo.hStdOutput = records_write;
        start.StartupInfo.hStdError = log;
        start.lpAttributeList = listed ? list : nullptr;

        std::wstring command = quoted(wide(engine));
        for (const std::string& a : args) command += L" " + quoted(wide(a));
        PROCESS_INFORMATION started{};
        // No console window of its own: the engine may run without one (started by Blender).
        const DWORD flags = CREATE_NO_WINDOW | (listed ? EXTENDED_STARTUPINFO_PRESENT : 0);
        const BOOL ok = CreateProcessW(wide(engine).c_str(), command.data(), nullptr, nullptr, TRUE, flags, nullptr,
                                       nullptr, &start.StartupInfo, &started);
        if (listed) DeleteProcThreadAttributeList(list);
        if (!ok) fail("CreateProcess");
        CloseHandle(started.hThread);
        close(jobs_read);
        close(records_write);
        close(log);
        handles_->process = started.hProcess;
        handles_->to_worker = jobs_write;
        handles_->from_worker = records_read;
    } catch (...) {
        close_all();
        throw;
    }
}

WorkerProcess::~WorkerProcess() {
    close(handles_->to_worker);
    if (!handles_->waited) {
        TerminateProcess(handles_->process, kKilledExit);
        WaitForSingleObject(handles_->process, INFINITE);
    }
    close(handles_->from_worker);
    close(handles_->process);
}

void WorkerProcess::send(const std::string& text) {
    size_t done = 0;
    while (done < text.size()) {
        DWORD written = 0;
        if (!WriteFile(handles_->to_worker, text.data() + done, static_cast<DWORD>(text.size() - done), &written,
                       nullptr) ||
            written == 0)
            return;
        done += written;
    }
}

bool WorkerProcess::output_waiting() const {
    DWORD available = 0;
    // A pipe whose writer is gone fails here: its end is waiting to be read.
    if (!PeekNamedPipe(handles_->from_worker, nullptr, 0, nullptr, &available, nullptr)) return true;
    return available > 0;
}

bool WorkerProcess::read_some(std::vector<uint8_t>& into) {
    uint8_t chunk[1 << 16];
    DWORD n = 0;
    if (!ReadFile(handles_->from_worker, chunk, sizeof chunk, &n, nullptr) || n == 0) return false;
    into.insert(into.end(), chunk, chunk + n);
    return true;
}

void WorkerProcess::kill() { TerminateProcess(handles_->process, kKilledExit); }

WorkerExit WorkerProcess::wait() {
    if (!handles_->waited) {
        WaitForSingleObject(handles_->process, INFINITE);
        GetExitCodeProcess(handles_->process, &handles_->exit_code);
        handles_->waited = true;
    }
    return describe_exit(handles_->exit_code);
}

std::vector<size_t> wait_for_output(const std::vector<WorkerProcess*>& workers, int timeout_ms) {
    // Anonymous pipes cannot be waited on together: look at each, then sleep a little.
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    std::vector<size_t> ready;
    for (;;) {
        for (size_t k = 0; k < workers.size(); ++k)
            if (workers[k]->output_waiting()) ready.push_back(k);
        if (!ready.empty() || workers.empty() || std::chrono::steady_clock::now() >= until) return ready;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

WorkerChannels take_worker_channels() {
    const bool piped = GetFileType(GetStdHandle(STD_INPUT_HANDLE)) == FILE_TYPE_PIPE &&
                       GetFileType(GetStdHandle(STD_OUTPUT_HANDLE)) == FILE_TYPE_PIPE;
    if (!piped) throw std::runtime_error("a worker runs only under the engine's supervisor (no job channel)");
    WorkerChannels channels{_dup(0), _dup(1)};
    if (channels.jobs_fd < 0 || channels.records_fd < 0)
        throw std::runtime_error("a worker cannot take its channels");
    _setmode(channels.jobs_fd, _O_BINARY);
    _setmode(channels.records_fd, _O_BINARY);
    // From here on, whatever prints goes to the log, never into a record.
    std::fflush(stdout);
    _dup2(2, 1);
    const int nothing = _open("NUL", _O_RDONLY);
    if (nothing >= 0) _dup2(nothing, 0);
    return channels;
}

namespace {

[[noreturn]] void end_with_signal(int sig) {
    TerminateProcess(GetCurrentProcess(), kFaultExitBase + static_cast<DWORD>(sig));
    for (;;) {
    }
}

// The C runtime's signal numbers differ from POSIX (SIGABRT is 22): each is ended as Linux's.
void on_signal(int sig) {
    end_with_signal(sig == SIGABRT ? kSigAbrt : sig == SIGILL ? kSigIll : sig == SIGFPE ? kSigFpe : kSigSegv);
}

LONG WINAPI on_exception(EXCEPTION_POINTERS* info) {
    switch (info->ExceptionRecord->ExceptionCode) {
        case EXCEPTION_ILLEGAL_INSTRUCTION:
        case EXCEPTION_PRIV_INSTRUCTION: end_with_signal(kSigIll);
        case EXCEPTION_FLT_DIVIDE_BY_ZERO:
        case EXCEPTION_FLT_INVALID_OPERATION:
        case EXCEPTION_FLT_OVERFLOW:
        case EXCEPTION_FLT_UNDERFLOW:
        case EXCEPTION_FLT_INEXACT_RESULT:
        case EXCEPTION_FLT_DENORMAL_OPERAND:
        case EXCEPTION_FLT_STACK_CHECK:
        case EXCEPTION_INT_DIVIDE_BY_ZERO:
        case EXCEPTION_INT_OVERFLOW: end_with_signal(kSigFpe);
        default: end_with_signal(kSigSegv);  // access violation, stack overflow, a bad page
    }
}

}  // namespace

void end_worker_quietly_on_faults() {
    // No "program has stopped working" box and no debugger: the supervisor records the fault.
    SetErrorMode(SEM_FAILCRITICALERRORS | SEM_NOGPFAULTERRORBOX | SEM_NOOPENFILEERRORBOX);
    SetUnhandledExceptionFilter(on_exception);
    for (int sig : {SIGABRT, SIGSEGV, SIGILL, SIGFPE}) std::signal(sig, on_signal);
}

std::string engine_executable(const std::string&) {
    std::wstring path(MAX_PATH, L'\0');
    for (;;) {
        const DWORD n = GetModuleFileNameW(nullptr, path.data(), static_cast<DWORD>(path.size()));
        if (n == 0) return {};
        if (n < path.size()) return utf8(path.substr(0, n));
        path.resize(path.size() * 2);
    }
}

}  // namespace mwb
