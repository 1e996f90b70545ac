#pragma once
// What a library file says about the run that produced it: the scene, the parameters, the codec
// bounds and the base seed. Files can be merged only when these agree (their run hash).
#include <cstdint>
#include <string>

#include "codec/CodecFormat.h"
#include "sim/SimulationParameters.h"

namespace mwb {

struct RunHeader {
    std::string scene_json;  ///< the engine's scene JSON, verbatim
    SimulationParameters parameters;
    CodecBounds bounds;
    uint64_t base_seed = 0;
    /// The engine build that sampled the run (common/BuildInfo); empty in libraries made before
    /// builds were recorded. Not part of the run hash: shards of one run may come from different
    /// builds (merge warns).
    std::string engine_build;
};

std::string run_header_to_json(const RunHeader& header);
/// Throws LibraryError naming `where` when the JSON is malformed or lacks a field.
RunHeader run_header_from_json(const std::string& text, const std::string& where);
/// Everything but the scene, as one flat JSON object: the simulation parameters, the codec
/// bounds (position_error_max_m, rotation_error_max_deg) and the base seed.
std::string run_settings_to_json(const RunHeader& header);
/// 16 hex digits identifying (scene, parameters, bounds, base seed); equal for shards of one run.
/// The engine build is left out.
std::string run_hash(const RunHeader& header);
/// 16 hex digits identifying the scene alone.
std::string scene_hash(const RunHeader& header);

}  // namespace mwb
