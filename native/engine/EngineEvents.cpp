#include "EngineEvents.h"

#include <cerrno>
#include <cstdio>
#include <iostream>
#include <thread>
#ifdef _WIN32
#include <io.h>
#else
#include <unistd.h>
#endif

#include "common/BuildInfo.h"

namespace mwb {
namespace {

int read_stdin(char* buffer, unsigned size) {
#ifdef _WIN32
    return ::_read(0, buffer, size);
#else
    for (;;) {
        const ssize_t n = ::read(STDIN_FILENO, buffer, size);
        if (n < 0 && errno == EINTR) continue;
        return static_cast<int>(n);
    }
#endif
}

// Events go out on a descriptor of their own, a copy of standard output; standard output itself
// then points at standard error (the log), where ODE's and the C library's prints land.
int take_stdout_for_events() {
    std::fflush(stdout);
#ifdef _WIN32
    const int events = ::_dup(1);
    if (events >= 0) ::_dup2(2, 1);
#else
    const int events = ::dup(STDOUT_FILENO);
    if (events >= 0) ::dup2(STDERR_FILENO, STDOUT_FILENO);
#endif
    return events >= 0 ? events : 1;
}

void write_whole(int fd, const std::string& text) {
    size_t done = 0;
    while (done < text.size()) {
#ifdef _WIN32
        const int n = ::_write(fd, text.data() + done, static_cast<unsigned>(text.size() - done));
#else
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
#endif
        if (n <= 0) return;  // the reader is gone: nobody is left to tell
        done += static_cast<size_t>(n);
    }
}

}  // namespace

EngineEvents::EngineEvents(bool as_json, bool show_progress)
    : as_json_(as_json), show_progress_(show_progress), events_fd_(as_json ? take_stdout_for_events() : 1) {}

void EngineEvents::write(const char* event, nlohmann::json fields) {
    fields["event"] = event;
    // One line per event, whole: a reader takes a line at a time.
    const std::string line = fields.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    std::lock_guard<std::mutex> lock(mutex_);
    write_whole(events_fd_, line);
}

void EngineEvents::start(const std::string& command) {
    if (as_json_) write("start", {{"protocol", kEngineProtocolVersion}, {"command", command}, {"engine_build", engine_build()}});
}

void EngineEvents::progress(uint64_t done, uint64_t total, const nlohmann::json& extra, const std::string& text) {
    if (as_json_) {
        nlohmann::json fields = extra.is_object() ? extra : nlohmann::json::object();
        fields["done"] = done;
        fields["total"] = total;
        fields["text"] = text;
        write("progress", std::move(fields));
    } else if (show_progress_) {
        std::lock_guard<std::mutex> lock(mutex_);
        std::cerr << "mwb-engine: " << text << "\n";
        std::cerr.flush();
    }
}

void EngineEvents::world(uint64_t index, bool stored, const std::string& reason) {
    if (as_json_) write("world", {{"index", index}, {"stored", stored}, {"reason", reason}});
}

void EngineEvents::warning(EngineWarningCode code, const std::string& message) {
    if (as_json_) {
        write("warning", {{"code", engine_warning_code_name(code)}, {"message", message}});
    } else {
        std::lock_guard<std::mutex> lock(mutex_);
        std::cerr << "mwb-engine: warning: " << message << "\n";
    }
}

void EngineEvents::error(EngineErrorCode code, const std::string& message, const std::vector<std::string>& problems,
                         const std::string& heading) {
    if (as_json_) {
        write("error", {{"code", engine_error_code_name(code)}, {"message", message}, {"problems", problems}});
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (!heading.empty()) {
        std::cerr << "mwb-engine: " << heading << "\n";
        for (const std::string& p : problems) std::cerr << p << "\n";
    } else {
        std::cerr << "mwb-engine: " << message << "\n";
    }
}

void EngineEvents::summary(nlohmann::json fields, const std::string& text) {
    if (as_json_) {
        fields["text"] = text;
        write("summary", std::move(fields));
    } else {
        std::lock_guard<std::mutex> lock(mutex_);
        std::cout << text;
        if (!text.empty() && text.back() != '\n') std::cout << "\n";
        std::cout.flush();
    }
}

void listen_for_cancel_on_stdin(std::atomic<bool>& cancel) {
    // Raw reads, never std::cin or stdio: a thread blocked inside stdio holds the stream's lock,
    // and fork() (the supervisor starting a worker) waits for every stdio lock: it would hang.
    std::thread([&cancel] {
        std::string line;
        char buffer[256];
        for (;;) {
            const auto n = read_stdin(buffer, sizeof buffer);
            if (n <= 0) return;  // the program closed our stdin (or it is /dev/null): nothing to hear
            for (int k = 0; k < n; ++k) {
                if (buffer[k] != '\n') {
                    if (line.size() < 64) line += buffer[k];
                    continue;
                }
                if (!line.empty() && line.back() == '\r') line.pop_back();
                if (line == "cancel") cancel.store(true);
                line.clear();
            }
        }
    }).detach();
}

}  // namespace mwb
