#include "common/EngineProtocol.h"

namespace mwb {

const char* engine_error_code_name(EngineErrorCode code) {
    switch (code) {
        case EngineErrorCode::Usage: return "usage";
        case EngineErrorCode::InvalidScene: return "invalid_scene";
        case EngineErrorCode::BadLibrary: return "bad_library";
        case EngineErrorCode::OtherRun: return "other_run";
        case EngineErrorCode::Refine: return "refine";
        case EngineErrorCode::Goal: return "goal";
        case EngineErrorCode::Internal: return "internal";
    }
    return "internal";
}

const char* engine_warning_code_name(EngineWarningCode code) {
    switch (code) {
        case EngineWarningCode::Repaired: return "repaired";
        case EngineWarningCode::OtherBuild: return "other_build";
        case EngineWarningCode::Merge: return "merge";
        case EngineWarningCode::InProcess: return "in_process";
        case EngineWarningCode::OdeMessage: return "ode_message";
    }
    return "merge";
}

std::vector<std::string> engine_event_names() {
    return {"start", "progress", "world", "warning", "error", "summary"};
}

std::vector<std::string> engine_error_code_names() {
    std::vector<std::string> names;
    for (int c = 0; c <= static_cast<int>(EngineErrorCode::Internal); ++c)
        names.push_back(engine_error_code_name(static_cast<EngineErrorCode>(c)));
    return names;
}

std::vector<std::string> engine_warning_code_names() {
    std::vector<std::string> names;
    for (int c = 0; c <= static_cast<int>(EngineWarningCode::OdeMessage); ++c)
        names.push_back(engine_warning_code_name(static_cast<EngineWarningCode>(c)));
    return names;
}

}  // namespace mwb
