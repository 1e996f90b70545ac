#pragma once
// The settings of a sampling run that a person chooses (the add-on's sidebar, the command line),
// and the one way they become a run header. The engine and the module both go through here, so
// "does this library hold this run?" has one answer whether a process is asked or not.
#include <cstdint>
#include <string>

#include "codec/CodecFormat.h"
#include "library/RunHeader.h"
#include "scene/Scene.h"
#include "sim/SimulationParameters.h"

namespace mwb {

/// Every setting that changes a run's worlds besides the scene and the world range. Threads are
/// not among them: a world is the same on any thread count. The defaults are the product's.
struct RunSettings {
    uint64_t seed = 0;
    double duration_s = SimulationParameters{}.duration_s;  ///< <= 0: the scene's frame range
    bool stop_at_rest = SimulationParameters{}.stop_at_rest;
    double alpha = SimulationParameters{}.alpha_linear;     ///< perturbation strength, linear and angular
    double position_error_m = CodecBounds{}.position_error_max_m;
    double rotation_error_deg = kDefaultRotationErrorDeg;
};

/// Writes `settings` into the parameters and bounds they govern; the others stay as given.
void apply_run_settings(const RunSettings& settings, SimulationParameters& parameters, CodecBounds& bounds);

/// The header a run of `scene` with `settings` writes (engine_build left empty: it is not part of
/// the run hash).
RunHeader run_header_for(const Scene& scene, const RunSettings& settings);

/// What a library file says about a run about to be sampled into it.
enum class LibraryHolding {
    New,    ///< no library there yet (or an empty file): the run starts it
    Same,   ///< it holds this run: new worlds are added to it
    Other,  ///< it holds another run: sampling into it is refused
};

/// Reads only the header of the library at `path`. Throws LibraryError when it is damaged.
LibraryHolding library_holding(const std::string& path, const RunHeader& run);

}  // namespace mwb
