#include "library/RunSettings.h"

#include "library/FileBytes.h"
#include "library/LibraryReader.h"
#include "scene/SceneJson.h"

namespace mwb {

void apply_run_settings(const RunSettings& settings, SimulationParameters& parameters, CodecBounds& bounds) {
    parameters.duration_s = settings.duration_s;
    parameters.stop_at_rest = settings.stop_at_rest;
    parameters.alpha_linear = parameters.alpha_angular = settings.alpha;
    bounds.position_error_max_m = settings.position_error_m;
    bounds.rotation_error_max_rad = rotation_bound_rad(settings.rotation_error_deg);
}

RunHeader run_header_for(const Scene& scene, const RunSettings& settings) {
    RunHeader header;
    header.scene_json = scene_to_json(scene);
    apply_run_settings(settings, header.parameters, header.bounds);
    header.base_seed = settings.seed;
    return header;
}

LibraryHolding library_holding(const std::string& path, const RunHeader& run) {
    if (!file_holds_bytes(path)) return LibraryHolding::New;
    return run_hash(read_run_header(path)) == run_hash(run) ? LibraryHolding::Same : LibraryHolding::Other;
}

}  // namespace mwb
