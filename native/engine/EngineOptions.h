#pragma once
// Command line of the mwb-engine executable: the process that samples worlds for Blender and
// for farm tasks, so ODE never runs inside Blender's process for bulk work.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "codec/CodecFormat.h"
#include "library/RunSettings.h"
#include "sim/SimulationParameters.h"

namespace mwb {

/// A user mistake on the command line; main prints the message on one line and exits with 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct EngineOptions {
    std::string command;  ///< sample | refine | seek | info | merge | validate | worker (internal)
    std::string scene_path;
    std::string output_path;            ///< sample: --out; merge: the merged library
    std::string library_path;           ///< refine, seek: --library (appended to)
    std::vector<std::string> inputs;
    uint64_t base_seed = 0;
    uint64_t first_world = 0;
    uint64_t world_count = 16;
    int threads = 0;
    bool json = false;
    uint64_t parent_world = 0;          ///< refine: the world to refine
    std::vector<uint32_t> bodies;       ///< refine: scene body indices
    double branch_time_s = -1;          ///< refine: where the new worlds leave the parent
    int64_t first_child = -1;           ///< refine: index of the first new world (-1: after the last)
    std::vector<std::string> add_bodies;     ///< refine: bodies of --scene to add to the world
    std::vector<std::string> remove_bodies;  ///< refine: objects to remove from the world
    std::vector<std::string> update_bodies;  ///< refine: objects of the world to redefine from --scene
    std::string goal_path;              ///< seek: the goal's boxes (JSON)
    uint64_t want = 1;                  ///< seek: worlds meeting the goal to find
    uint64_t budget_worlds = 0;         ///< seek: at most this many worlds made
    double budget_s = 0;                ///< seek: and at most this long (0: no limit)
    bool progress = false;
    bool events = false;                ///< JSON-lines events on stdout (common/EngineProtocol.h)
    bool in_process = false;            ///< sample, refine, seek: simulate in this process, not in supervised workers
    /// sample: worlds that start alike share their prefix (sim/SharedPrefix); off only to measure it
    bool share_prefix = true;
    double world_time_limit_s = 0;      ///< sample, refine, seek: a world still running after this is rejected (0: adaptive)
    RunSettings run;                    ///< sample: the settings a person chose (seed is base_seed)
    SimulationParameters parameters;    ///< `run` applied, and the flags only the engine has
    CodecBounds bounds;                 ///< `run` applied
};

/// Parses argv; throws UsageError with a one-line message.
EngineOptions parse_engine_options(const std::vector<std::string>& args);
const char* engine_usage();

}  // namespace mwb
