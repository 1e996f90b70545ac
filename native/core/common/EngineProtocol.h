#pragma once
// The contract between mwb-engine and the programs that start it (the add-on, the command line,
// farm tasks). With --events the engine writes one JSON object per line on its standard output
// and nothing else there; each has an "event" key naming one of kEngineEvents. The program asks
// a run to stop by writing "cancel" and a newline to the engine's standard input.
//
// Version 2 events (every one also has "event"):
//   start     protocol, command, engine_build
//   progress  done, total (worlds of this command), text (the line for people); a seek adds
//             "seek": {boxes_met, box_count, worlds_made, worlds_rejected, best_world,
//             worlds_meeting_goal}
//   world     index, stored (false: rejected), reason (empty when stored)
//   warning   code (one of kWarningCodes), message
//   error     code (one of kErrorCodes), message; problems: every line of an invalid scene
//   summary   text (what the engine would print for people), rejected_text (sample, refine and
//             seek: "8 rejected (...)", empty when none) and the command's own fields
// Front ends show `text` and `rejected_text` as they are: the engine words its runs (RunWords.h).
// The exit status is an EngineExit.
#include <string>
#include <vector>

namespace mwb {

constexpr int kEngineProtocolVersion = 2;

/// The process's exit status; a program tells outcomes apart by these, never by message text.
enum class EngineExit : int {
    Ok = 0,
    Failed = 1,        ///< an unexpected failure (the error event says what)
    Usage = 2,         ///< the command, its options, the refinement or the goal do not fit
    InvalidScene = 3,  ///< the scene JSON is not a scene this engine can simulate
    BadLibrary = 4,    ///< the library cannot be read or written, or holds another run
    Cancelled = 130,   ///< stopped on request; every finished world is stored
};

/// Why a command failed: the `code` of its error event.
enum class EngineErrorCode {
    Usage,
    InvalidScene,
    BadLibrary,
    OtherRun,  ///< the library holds another run (scene, settings or seed changed)
    Refine,
    Goal,
    Internal,
};

/// What a warning is about: the `code` of a warning event.
enum class EngineWarningCode {
    Repaired,     ///< the library's torn last record was cut off before appending
    OtherBuild,   ///< the library was sampled by another engine build
    Merge,        ///< something merging libraries noticed
    InProcess,    ///< no worker process could be started: worlds are simulated in the engine's own
    OdeMessage,   ///< ODE gave a message while worlds stepped (which worlds, when)
};

const char* engine_error_code_name(EngineErrorCode code);
const char* engine_warning_code_name(EngineWarningCode code);
/// Every event name, error code and warning code the engine can write, in declaration order.
std::vector<std::string> engine_event_names();
std::vector<std::string> engine_error_code_names();
std::vector<std::string> engine_warning_code_names();

}  // namespace mwb
