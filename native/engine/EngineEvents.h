#pragma once
// What the engine tells the program that started it (common/EngineProtocol.h): JSON lines on
// standard output with --events, or the same happenings as text for a person at a terminal.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/EngineProtocol.h"

namespace mwb {

class EngineEvents {
public:
    /// as_json: every event a JSON line on stdout, nothing else there (from then on, whatever the
    /// process prints to stdout goes to stderr). Otherwise text: summaries on stdout; warnings,
    /// errors and (with show_progress) progress on stderr.
    EngineEvents(bool as_json, bool show_progress);

    bool as_json() const { return as_json_; }
    void start(const std::string& command);
    /// `extra`: fields a command adds (a seek's best world); `text`: the line for people.
    void progress(uint64_t done, uint64_t total, const nlohmann::json& extra, const std::string& text);
    void world(uint64_t index, bool stored, const std::string& reason);
    void warning(EngineWarningCode code, const std::string& message);
    /// `problems`: every problem when there are several (an invalid scene lists each); a person
    /// then reads `heading` and the problems a line each instead of `message`.
    void error(EngineErrorCode code, const std::string& message, const std::vector<std::string>& problems = {},
               const std::string& heading = "");
    /// `fields`: the command's outcome; `text`: what a person reads (several lines allowed).
    void summary(nlohmann::json fields, const std::string& text);

private:
    void write(const char* event, nlohmann::json fields);

    bool as_json_;
    bool show_progress_;
    int events_fd_;  ///< where JSON events go: standard output as the engine started
    std::mutex mutex_;  // worlds finish on several threads
};

/// Sets `cancel` when a line "cancel" arrives on standard input: how a program stops a run on
/// every OS (no signals). Returns at once; the listening thread lives until the process ends.
void listen_for_cancel_on_stdin(std::atomic<bool>& cancel);

}  // namespace mwb
