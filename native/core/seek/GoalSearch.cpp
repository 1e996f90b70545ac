#include "seek/GoalSearch.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include "library/LibraryReader.h"
#include "library/LibraryWriter.h"
#include "refine/StoredWorldRefinement.h"
#include "scene/SceneJson.h"
#include "seek/BranchPlanner.h"
#include "seek/FamilyAllowance.h"
#include "query/ScreenBox.h"
#include "seek/GoalJson.h"
#include "seek/ScoredWorlds.h"

namespace mwb {
namespace {

// Polylines at 30 Hz: the browser's own rate, so the search sees worlds as the user does.
constexpr double kPolylineHz = 30;
// A refinement helps when a child meets another box or comes this much closer to the next one;
// smaller gains would keep the search polishing one world instead of backing up.
constexpr double kMeaningfulGain = 0.02;
// The beam: 4 worlds (SeekRequest::beam_width), at most one from each sampled world's family, which
// keeps the search from spending everything on the descendants of a single lucky start (on the
// quick-start goal, from the same 8 worlds and 6 seeds, the most it took fell from 1,000 worlds to
// 424, and the staircase got as far).
//
// A family more than 3 parts behind the leading one gives its own beam place to the leading
// families' next best worlds. On the staircase (21 parts; base seeds 0 and 1, 10 minutes each) the
// two families 10 parts behind made 458 worlds for 2 parts between them, while the leader, 20 of 21
// parts met 4 minutes in, made 177 after it; from base seed 0 two families 5 and 6 parts behind
// made 554 worlds for 3 parts. Families within reach keep their places, so the beam still holds
// starts as good as the leader's, but a start half the goal behind no longer slows the best one.
//
// Unless it is well ahead of the leader's pace: 2 ordered parts ahead when it met its last takes
// the beam's last place. From the staircase's base seed 0 the leading families met 7, 6 and 5 of
// the 12 steps by 38 s of 40, while a family sampled at world 1,349 had met 3 by 4.9 s (the leader
// 1); it waited behind them, first refined at world 2,640, and met the whole goal 330 worlds later.
// These are BeamRule's own values; only the width is the request's.
BeamRule beam_rule(const SeekRequest& request) {
    BeamRule rule;
    rule.width = request.beam_width;
    return rule;
}
// The worlds a family whose best world broke a negative part before meeting any positive one may
// make without meeting more parts before it gives its place up to a fresh batch: eight refinements.
// Such a start is mended only by branching before the break and re-running all that came after,
// which a fresh world does for one world instead of eight. On the staircase (most sampled worlds
// poke an arm out in their first 1.5 s) broken families kept their beam places for 700 worlds and
// more without a gain, while families sampled later with a clean start went from 11 to 20 parts in
// 280 worlds. A family that met positive parts before it broke keeps the whole allowance: a
// refinement keeps them, a fresh world does not (from the staircase's base seed 3 the search got to
// 20 of 21 parts instead of 17).
constexpr uint64_t kBrokenFamilyWorlds = 64;

// The search's driver: the budget, the rounds of beam and refinement, fresh samples when
// refinement stalls, and what it reports. Scoring is ScoredWorlds', branching BranchPlanner's.
class GoalSearch {
public:
    GoalSearch(const std::string& path, const SeekRequest& request, const SeekListener& on_status,
               SamplingProgress* progress, WorldMaker* maker, const MadeWorldSink& on_world)
        : request_(request),
          on_status_(on_status),
          on_world_(on_world),
          progress_(progress ? progress : &own_progress_),
          reader_(path, ReaderOptions{false, kPolylineHz}),
          writer_(path, reader_.header()),
          scene_(scene_from_json(reader_.scene_json())),
          own_maker_(request.threads, request.cache_bytes),
          maker_(maker ? *maker : own_maker_),
          start_(std::chrono::steady_clock::now()),
          allowance_(request.family_stall_worlds, kBrokenFamilyWorlds) {
        check_request();
        worlds_.emplace(reader_, scene_, request_.boxes, request_.threads);
        planner_.emplace(scene_, request_.boxes, request_.seed);
    }

    SeekOutcome run() {
        if (reader_.worlds().empty()) sample_batch();
        worlds_->take_new_worlds();
        report();
        while (!finished()) {
            if (sampling_pays()) {
                sample_batch();
                worlds_->take_new_worlds();
                report();
                continue;
            }
            std::vector<uint64_t> beam = worlds_->choose_beam(beam_rule(request_));
            if (beam.empty()) {
                // Every good world's branch points are spent: start over from new sampled worlds.
                sample_batch();
                worlds_->take_new_worlds();
                report();
                continue;
            }
            for (uint64_t world : beam) {
                if (finished()) break;
                refine_once(world);
                report();
            }
        }
        return outcome();
    }

private:
    void check_request() const {
        if (request_.want == 0) throw GoalError("the number of worlds to find must be at least 1");
        if (request_.budget_worlds == 0) throw GoalError("the budget must allow at least one world");
        if (request_.budget_s < 0) throw GoalError("the time budget must not be negative");
        if (request_.family_stall_worlds == 0) throw GoalError("a family's allowance of worlds must be at least 1");
        try {
            check_goal(request_.boxes);
        } catch (const std::invalid_argument& error) {
            throw GoalError(error.what());
        }
        for (size_t k = 0; k < request_.boxes.size(); ++k)
            for (uint32_t body : request_.boxes[k].bodies)
                if (body >= scene_.bodies.size())
                    throw GoalError("box " + std::to_string(k + 1) + " names body " + std::to_string(body) +
                                    ", which the library's scene does not have");
    }

    double elapsed() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

    bool out_of_budget() const {
        return made_ >= request_.budget_worlds || (request_.budget_s > 0 && elapsed() >= request_.budget_s);
    }

    bool finished() const {
        return worlds_->found().size() >= request_.want || out_of_budget() || progress_->cancel.load();
    }

    void refine_once(uint64_t world) {
        Branch branch;
        if (!planner_->choose(world, worlds_->stored(world), worlds_->score(world), branch)) {
            worlds_->spend(world);
            return;
        }
        const StoredWorld& parent = worlds_->stored(world);
        RefineRequest refine;
        refine.parent_world = world;
        refine.bodies = branch.bodies;
        // The middle of the frame: it snaps down to exactly this frame.
        refine.branch_time_s = (static_cast<double>(branch.frame) + 0.5) / parent.record_hz;
        refine.count = std::min<uint64_t>(request_.children_per_branch, request_.budget_worlds - made_);
        refine.threads = request_.threads;
        RefineOutcome outcome;
        try {
            outcome = refine_stored_world(reader_, refine, writer_, maker_, on_world_, progress_);
        } catch (const WorldNotReproduced&) {
            throw;  // another build's library: no branch point of it can be refined here
        } catch (const RefineError&) {
            return;  // this branch point does not fit (e.g. a body that is not simulated there); others may
        }
        made_ += refine.count;
        count_rejections(outcome.statistics);
        refined_worlds_ += refine.count;
        ++refinements_;
        const double parts_before = std::floor(worlds_->best_value());
        worlds_->take_new_worlds();
        parts_gained_ += std::max(0.0, std::floor(worlds_->best_value()) - parts_before);
        std::vector<std::pair<uint64_t, double>> children;
        for (uint64_t child = outcome.first_child; child < outcome.first_child + refine.count; ++child)
            if (worlds_->has(child)) children.emplace_back(child, worlds_->score(child).value());
        planner_->note_children(world, worlds_->score(world).value(), children, kMeaningfulGain);
        note_family_progress(world, children, refine.count);
        note_progress();
    }

    // Sets a family aside for good once its refinements have made request_.family_stall_worlds
    // worlds (kBrokenFamilyWorlds while its best world broke a negative part first, and then a
    // fresh batch is sampled) since one of them last met more parts than any of the family before:
    // its place in the beam goes to the next family, which may be one sampled meanwhile. On
    // SIGGRAPH the families that reached the goal gained each letter within 736 of their worlds
    // (from base seed 1: 88 to 359 for the one that got all 8), while from base seed 0 four
    // families made 1,278 to 1,659 worlds each after their last gain until the 10 minutes ran out,
    // and the batches sampled meanwhile never got a place in the beam: hence 1,024.
    void note_family_progress(uint64_t world, const std::vector<std::pair<uint64_t, double>>& children,
                              uint64_t made) {
        const auto as_seen = [&](uint64_t w) {
            const GoalScore& s = worlds_->score(w);
            return FamilyWorld{s.value(), std::isfinite(s.violation_time_s) && s.positive_parts_before_violation == 0};
        };
        std::vector<FamilyWorld> scored;
        for (const auto& child : children) scored.push_back(as_seen(child.first));
        const uint64_t family = worlds_->family_of(world);
        const FamilyAllowance::Verdict verdict = allowance_.note(family, as_seen(world), scored, made);
        if (verdict == FamilyAllowance::Verdict::Keep) return;
        worlds_->set_aside(family);
        if (verdict == FamilyAllowance::Verdict::BrokenStart) {
            sample_batch();
            worlds_->take_new_worlds();
            made_at_progress_ = made_;
        }
    }

    // Fresh sampled worlds when refinement has stopped getting anywhere: a new start may succeed
    // where every branch of the old ones failed. One batch per stall, so on a goal that a single
    // chaotic event decides (the trebuchet's) the search is no faster than sampling.
    void note_progress() {
        const double best = worlds_->best_value();
        if (best > best_value_ + kMeaningfulGain) {
            best_value_ = best;
            made_at_progress_ = made_;
        } else if (made_ - made_at_progress_ >= stagnation_worlds()) {
            sample_batch();
            worlds_->take_new_worlds();
            made_at_progress_ = made_;
        }
    }

    // Whether sampling afresh is likelier to meet the goal soon than refining: the worlds a fresh
    // one takes on average (by the odds of those so far) against the worlds refinement took per
    // part it gained, times the parts the best world still misses. Before it gained any, a part
    // is taken to cost what refinement may spend before it counts as stalled. Where every part
    // is common (the quick start's three bins, 1 fresh world in 110), refining alone took about
    // 5 times the worlds sampling does; where some part is rare (SIGGRAPH's letters, about 1 in
    // 10^9 together), this never samples. Not before a refinement has shown that this build
    // reproduces the library's worlds: its fresh worlds must not go into another build's library.
    bool sampling_pays() const {
        if (refinements_ == 0) return false;
        const double odds = worlds_->sampled_goal_odds();
        const double missing = static_cast<double>(request_.boxes.size()) - std::floor(worlds_->best_value());
        const double per_part =
            static_cast<double>(refined_worlds_ + stagnation_worlds()) / (parts_gained_ + 1);
        return odds * per_part * missing > 1.0;
    }

    uint64_t stagnation_worlds() const {
        return std::max<uint64_t>(256, uint64_t{8} * request_.beam_width * request_.children_per_branch);
    }

    void sample_batch() {
        const uint64_t count = std::min(request_.first_batch, request_.budget_worlds - made_);
        if (count == 0) return;
        const RunHeader& header = reader_.header();
        // The scene as sampled: bodies added to worlds since are not in fresh samples.
        const CompiledScene compiled(scene_from_json(header.scene_json), header.parameters);
        std::vector<uint64_t> indices;
        for (uint64_t k = 0; k < count; ++k) indices.push_back(reader_.next_world_index() + k);
        count_rejections(maker_.sample(compiled, header.base_seed, indices, writer_, on_world_, progress_));
        made_ += count;
        // Worlds sampled now are new candidates; spent ones stay spent.
    }

    void count_rejections(const SamplingStatistics& made) {
        rejected_ += made.worlds_rejected;
        for (const auto& [reason, count] : made.reject_reasons) reject_reasons_[reason] += count;
        merge_ode_messages(ode_messages_, made.ode_messages);
    }

    SeekStatus status() const {
        SeekStatus s;
        s.box_count = static_cast<uint32_t>(request_.boxes.size());
        if (!worlds_->empty()) {
            s.best_world = worlds_->best_world();
            s.best_value = worlds_->score(s.best_world).value();
            s.best_boxes_met = worlds_->score(s.best_world).boxes_met;
        }
        s.worlds_made = made_;
        s.worlds_rejected = rejected_;
        s.worlds_meeting_goal = worlds_->found().size();
        s.seconds = elapsed();
        return s;
    }

    void report() const {
        if (on_status_) on_status_(status());
    }

    SeekOutcome outcome() const {
        SeekOutcome out;
        static_cast<SeekStatus&>(out) = status();
        out.reached = worlds_->found().size() >= request_.want;
        out.cancelled = progress_->cancel.load();
        out.found.assign(worlds_->found().begin(), worlds_->found().end());
        if (!worlds_->empty()) out.best_score = worlds_->score(worlds_->best_world());
        out.refinements = refinements_;
        out.reject_reasons = reject_reasons_;
        out.ode_messages = ode_messages_;
        return out;
    }

    SeekRequest request_;
    SeekListener on_status_;
    MadeWorldSink on_world_;
    uint64_t rejected_ = 0;
    std::map<std::string, uint64_t> reject_reasons_;
    OdeMessageReports ode_messages_;
    SamplingProgress own_progress_;
    SamplingProgress* progress_;
    LibraryReader reader_;
    LibraryWriter writer_;
    Scene scene_;
    InProcessWorlds own_maker_;
    WorldMaker& maker_;
    std::chrono::steady_clock::time_point start_;
    // Made once the request is checked (they take its goal order and bodies as given).
    std::optional<ScoredWorlds> worlds_;
    std::optional<BranchPlanner> planner_;
    uint64_t made_ = 0, refinements_ = 0, refined_worlds_ = 0;
    double parts_gained_ = 0;  ///< by refinements: parts the best world gained when they made it
    double best_value_ = -1;
    uint64_t made_at_progress_ = 0;
    FamilyAllowance allowance_;
};

}  // namespace

std::vector<uint64_t> worlds_meeting_goal(const std::string& library_path, const std::string& goal_json, int threads) {
    LibraryReader reader(library_path, ReaderOptions{false, kPolylineHz});
    const Scene scene = scene_from_json(reader.scene_json());
    const std::vector<QueryBox> goal = goal_from_json(goal_json, scene);
    ScoredWorlds worlds(reader, scene, goal, threads);
    worlds.take_new_worlds();
    return {worlds.found().begin(), worlds.found().end()};
}

SeekOutcome seek_goal(const std::string& library_path, const SeekRequest& request, const SeekListener& on_status,
                      SamplingProgress* progress, WorldMaker* maker, const MadeWorldSink& on_world) {
    GoalSearch search(library_path, request, on_status, progress, maker, on_world);
    return search.run();
}

}  // namespace mwb
