#pragma once
// Goal search: refine a library's worlds again and again, by itself, until worlds meet every box
// of a goal — what a user does by hand with refine, look, refine again. It only samples and
// refines, so every world it makes is an ordinary world of the library, with its lineage.
//
// Each round keeps a beam of the best worlds (most parts met along the order before the first
// entry into a negative part, then closest to the next part). Each beam world is refined where
// its first unmet box went wrong: before that box's window, at the collisions of the bodies that
// missed it, and at the collisions of the bodies that hit them; how late in that span is learnt
// from which refinements paid. When the worlds sampled so far say fresh ones meet the goal sooner
// than refinement gains parts, or refinement stalls, it samples afresh instead; a family (a
// sampled world and its refinements) whose refinements stop meeting more parts leaves the beam
// to the next.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "query/GoalScore.h"
#include "query/PathIndex.h"
#include "refine/WorldMaker.h"
#include "sampler/Sampler.h"

namespace mwb {

struct SeekRequest {
    std::vector<QueryBox> boxes;     ///< the goal, body indices of the library's current scene
    uint64_t want = 1;               ///< stop when this many worlds of the library meet the goal
    uint64_t budget_worlds = 2000;   ///< at most this many worlds simulated
    double budget_s = 0;             ///< and at most this long (0: no limit)
    uint64_t seed = 0;               ///< the search's own choices (which branch point to try)
    int threads = 0;                 ///< <= 0: all cores
    uint32_t beam_width = 4;
    uint32_t children_per_branch = 8;
    uint64_t first_batch = 32;       ///< worlds sampled first when the library has none
    /// A family (a sampled world and its descendants) leaves the beam once its refinements made
    /// this many worlds without one meeting more parts than the family had (see GoalSearch.cpp).
    uint64_t family_stall_worlds = 1024;
    size_t cache_bytes = size_t{2} << 30;  ///< worlds kept in memory to refine them again
};

struct SeekStatus {
    uint32_t box_count = 0;
    uint32_t best_boxes_met = 0;
    double best_value = 0;            ///< GoalScore::value() of the best world
    uint64_t best_world = 0;
    uint64_t worlds_made = 0;         ///< simulated by this search (sampled, refined, rejected)
    uint64_t worlds_rejected = 0;     ///< of those, rejected (a fault, a time limit, a runaway body)
    uint64_t worlds_meeting_goal = 0; ///< in the whole library
    double seconds = 0;
};

struct SeekOutcome : SeekStatus {
    bool reached = false;              ///< `want` worlds meet the goal
    bool cancelled = false;
    std::vector<uint64_t> found{};     ///< every world of the library meeting the goal
    GoalScore best_score{};
    uint64_t refinements = 0;          ///< refine calls made
    std::map<std::string, uint64_t> reject_reasons{};  ///< why worlds were rejected -> how many
    OdeMessageReports ode_messages{};                   ///< what ODE said while the worlds stepped
};

/// Called after each batch of new worlds, from the calling thread.
using SeekListener = std::function<void(const SeekStatus&)>;

/// The worlds of the library at `library_path` meeting the goal file `goal_json` (boxes and
/// orientation parts, see GoalJson.h), scored as the search scores them; ascending. Throws
/// GoalError and LibraryError as seek_goal does.
std::vector<uint64_t> worlds_meeting_goal(const std::string& library_path, const std::string& goal_json, int threads = 0);

/// Searches the library at `library_path` (appending to it) for worlds meeting `request.boxes`.
/// Deterministic: the same library, goal, budget in worlds and seed give the same worlds on any
/// number of threads. Setting progress->cancel stops it at the next world; every world made so
/// far is in the file. Throws GoalError for a goal that does not fit the library,
/// WorldNotReproduced when its worlds were made by another engine build, and LibraryError when
/// the file cannot be read or written. `maker` simulates the worlds (nullptr: this process's
/// threads, keeping up to request.cache_bytes of lineages).
/// `on_world` (optional) is told of each world as it arrives, between the listener's batches.
SeekOutcome seek_goal(const std::string& library_path, const SeekRequest& request, const SeekListener& on_status = {},
                      SamplingProgress* progress = nullptr, WorldMaker* maker = nullptr,
                      const MadeWorldSink& on_world = {});

}  // namespace mwb
