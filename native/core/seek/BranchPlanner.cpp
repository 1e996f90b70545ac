#include "seek/BranchPlanner.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/PortableMath.h"

namespace mwb {
namespace {

// Branch points just before a box's window opens, seconds.
constexpr double kBeforeWindow[] = {0.1, 0.25, 0.5, 1.0, 2.0};
// Spacing of the fallback branch points when nothing collided in the span, seconds.
constexpr double kGridSpacing = 0.5;
// A world still nearing the part it misses this close to its end ran out of time, seconds.
constexpr double kRunningOutS = 1.0;
// Negative boxes entered by many bodies: the earliest few are refined.
constexpr size_t kMaxFailingBodies = 8;
// The first step of a broken world's back-off in time, seconds (then 0.2, 0.4, ...).
constexpr double kBackOffStepS = 0.1;

// When the last of `bodies` came to rest for good (the world's end if one never did).
double rest_time(const StoredWorld& w, const std::set<uint32_t>& bodies) {
    const double world_end = (w.first_frame + w.frame_count - 1) / w.record_hz;
    for (const MetricValues& m : w.metrics) {
        if (m.name != "time_to_rest_s") continue;
        double last = 0;
        for (uint32_t b : bodies) last = std::max(last, b < m.per_body.size() ? m.per_body[b] : world_end);
        return last;
    }
    return world_end;
}

}  // namespace

BranchPlanner::BranchPlanner(const Scene& scene, const std::vector<QueryBox>& boxes, uint64_t seed)
    : scene_(scene), boxes_(boxes), random_(seed ^ 0x5eecULL) {}

bool BranchPlanner::simulated(uint32_t body) const {
    return body < scene_.bodies.size() && body_role(scene_.bodies[body]) == BodyRole::Simulated;
}

std::vector<Branch> BranchPlanner::branch_points(const StoredWorld& w, const GoalScore& score,
                                                 const GoalScore::Miss& miss, RiskPass pass,
                                                 std::vector<size_t>& lateness) const {
    const QueryBox& box = boxes_[static_cast<size_t>(miss.part)];
    // A box offers every point risking met parts in its second pass, so none is left for a third.
    if (pass == RiskPass::RisksMany && !box.orientation) return {};
    const double hz = w.record_hz;
    const double world_end = (w.first_frame + w.frame_count - 1) / hz;
    // Keep what the boxes before it in the order achieved, all but the last: branch after the
    // box two before it was met. Branching only after the box it follows leaves too little
    // to change when the world got there already stopping (a body coming to rest on the step
    // it just reached); later points are still tried first, so the last box is kept when it can be.
    double lower = 0.0;
    if (box.after >= 0) {
        const int32_t earlier = boxes_[static_cast<size_t>(box.after)].after;
        lower = earlier >= 0 ? score.met_time_s[static_cast<size_t>(earlier)] : 0.0;
        // A miss of pace, not of place, may be mended anywhere on the way: the world was in the
        // box before its window opened and went on (too fast), or was still on its way to it when
        // it ended (too slow). On the staircase the leading families met every step box by 24-28 s and slid
        // off the bottom by 30, the end box's window being the last second; others met their 6th
        // and 7th step box 39.8 and 39.6 s into the 40, one after resting 28 s on a tread. Their
        // refinements all branched after the step box two before, and the families made 480 to
        // 1,037 worlds more without meeting another part.
        const bool too_fast = std::isfinite(miss.early_visit_s);
        const bool too_slow = miss.failure_time_s > world_end - kRunningOutS;
        if (too_fast || too_slow) lower = 0.0;
    }
    double upper = std::min(miss.failure_time_s, world_end);
    if (!(upper > lower)) upper = world_end;
    std::vector<uint32_t> failing;
    for (uint32_t b : miss.failing_bodies)
        if (simulated(b) && failing.size() < kMaxFailingBodies) failing.push_back(b);
    if (failing.empty())
        for (uint32_t b : box.bodies)
            if (simulated(b) && failing.size() < kMaxFailingBodies) failing.push_back(b);
    if (failing.empty()) return {};
    // The bodies that missed, with everything jointed to them: an arm's impact turns the body.
    const std::set<uint32_t> failing_set = jointed_with(failing);
    // Branching after they all came to rest changes nothing (unless something hits them). All of
    // them: a limb lying still while the body it hangs from slides on is moved on by that body's
    // impacts, at which the children are branched too.
    const double rest = rest_time(w, failing_set);
    if (rest + 1 / hz < upper) upper = rest + 1 / hz;
    if (!(upper > lower)) upper = world_end;
    // Nothing after the world broke a negative part counts (GoalScore::parts_before_violation): a
    // branch later than that leaves the break as it was, and every child scores as its parent. On
    // the staircase 12 of a search's first 33 refinements branched there, for a step box further
    // down, and 10 of them made 8 children no different from their parent.
    if (std::isfinite(score.violation_time_s)) {
        upper = std::min(upper, score.violation_time_s);
        if (!(upper > lower)) return {};
    }

    std::set<Branch> points;
    auto add = [&](double t, std::vector<uint32_t> bodies) {
        if (!(t >= lower && t < upper)) return;
        std::sort(bodies.begin(), bodies.end());
        bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
        points.insert({static_cast<uint64_t>(std::floor(t * hz)), std::move(bodies)});
    };
    // Collisions of those bodies, and of the simulated bodies that hit them.
    std::set<uint32_t> hitters;
    for (const ContactEvent& c : w.contacts) {
        if (c.body < 0 || !failing_set.count(static_cast<uint32_t>(c.body))) continue;
        add(c.time_s, failing);
        if (c.other >= 0 && simulated(static_cast<uint32_t>(c.other)) && !failing_set.count(static_cast<uint32_t>(c.other)) &&
            c.time_s >= lower && c.time_s < upper)
            hitters.insert(static_cast<uint32_t>(c.other));
    }
    for (const ContactEvent& c : w.contacts) {
        if (c.body < 0 || !hitters.count(static_cast<uint32_t>(c.body))) continue;
        std::vector<uint32_t> bodies = failing;
        bodies.push_back(static_cast<uint32_t>(c.body));
        add(c.time_s, bodies);
    }
    // Just before the box's window opens.
    const double opens = box.window.empty() ? upper : std::max(box.window.lo_s, miss.window_start_s);
    for (double before : kBeforeWindow) add(opens - before, failing);
    if (points.size() < 4)
        for (double t = lower; t < upper; t += kGridSpacing) add(t, failing);
    // Which bodies holding a met part a point may put at risk, by pass: none; then any for a box,
    // at most kFewRisked for a pose; then, for a pose, more.
    size_t fewest = 0, most = 0;
    if (pass == RiskPass::RisksFew) fewest = 1, most = box.orientation ? kFewRisked : std::numeric_limits<size_t>::max();
    if (pass == RiskPass::RisksMany) fewest = kFewRisked + 1, most = std::numeric_limits<size_t>::max();
    std::vector<Branch> worth = worth_branching(w, score, failing_set, points, fewest, most);
    lateness.clear();
    for (const Branch& point : worth) {
        const double fraction = (static_cast<double>(point.frame) / hz - lower) / (upper - lower);
        lateness.push_back(std::min(kLatenessBins - 1, static_cast<size_t>(std::max(0.0, fraction) * kLatenessBins)));
    }
    return worth;
}

std::vector<Branch> BranchPlanner::worth_branching(const StoredWorld& w, const GoalScore& score,
                                                   const std::set<uint32_t>& failing_set,
                                                   const std::set<Branch>& points, size_t fewest_risked,
                                                   size_t most_risked) const {
    // The bodies holding a part already met (the failing bodies aside: they are to change).
    std::set<uint32_t> kept;
    for (size_t k = 0; k < boxes_.size(); ++k) {
        const QueryBox& part = boxes_[k];
        if (part.negative || k >= score.met.size() || !score.met[k] || waits_on_missed_box(boxes_, score, k)) continue;
        for (uint32_t b : part.bodies)
            if (simulated(b) && !failing_set.count(b)) kept.insert(b);
    }
    // The impacts that count (none after the world broke a negative part: nothing after that
    // counts), and the touches between simulated bodies, in time order.
    std::vector<const ContactEvent*> impacts, touches;
    for (const ContactEvent& c : w.contacts) {
        if (c.body < 0) continue;
        if (c.time_s < score.violation_time_s) impacts.push_back(&c);
        if (c.other >= 0 && simulated(static_cast<uint32_t>(c.body)) && simulated(static_cast<uint32_t>(c.other)))
            touches.push_back(&c);
    }
    const auto by_time = [](const ContactEvent* x, const ContactEvent* y) { return x->time_s < y->time_s; };
    std::stable_sort(impacts.begin(), impacts.end(), by_time);
    std::stable_sort(touches.begin(), touches.end(), by_time);
    std::vector<Branch> worth;
    for (const Branch& point : points) {
        // The children re-simulate from the start of the branch frame.
        const double branch_time = static_cast<double>(point.frame) / w.record_hz;
        std::set<uint32_t> reached = jointed_with(point.bodies);
        const auto from = std::lower_bound(impacts.begin(), impacts.end(), branch_time,
                                           [](const ContactEvent* c, double t) { return c->time_s < t; });
        if (std::none_of(from, impacts.end(), [&](const ContactEvent* c) { return reached.count(static_cast<uint32_t>(c->body)) > 0; }))
            continue;
        // What the refined bodies touch from then on, what those touch after, and so on: the
        // bodies a child may set moving anew, its own touches or its ghosts'.
        size_t risked = static_cast<size_t>(std::count_if(reached.begin(), reached.end(), [&](uint32_t b) { return kept.count(b) > 0; }));
        for (const ContactEvent* c : touches) {
            if (risked > most_risked) break;
            if (c->time_s < branch_time) continue;
            const auto a = static_cast<uint32_t>(c->body), o = static_cast<uint32_t>(c->other);
            if (reached.count(a) == reached.count(o)) continue;
            for (uint32_t b : jointed_with({reached.count(a) ? o : a}))
                if (reached.insert(b).second && kept.count(b)) ++risked;
        }
        if (risked >= fewest_risked && risked <= most_risked) worth.push_back(point);
    }
    return worth;
}

std::set<uint32_t> BranchPlanner::jointed_with(const std::vector<uint32_t>& bodies) const {
    std::set<uint32_t> group(bodies.begin(), bodies.end());
    for (bool grew = true; grew;) {
        grew = false;
        for (const Constraint& c : scene_.constraints) {
            if (!c.enabled) continue;
            const int a = scene_.body_index(c.body_a), b = scene_.body_index(c.body_b);
            if (a < 0 || b < 0 || !simulated(static_cast<uint32_t>(a)) || !simulated(static_cast<uint32_t>(b))) continue;
            const bool has_a = group.count(static_cast<uint32_t>(a)) > 0, has_b = group.count(static_cast<uint32_t>(b)) > 0;
            if (has_a != has_b) {
                group.insert(static_cast<uint32_t>(has_a ? b : a));
                grew = true;
            }
        }
    }
    return group;
}

bool BranchPlanner::choose(uint64_t world, const StoredWorld& record, const GoalScore& score, Branch& chosen) {
    // The parts it could meet next, those its refinements failed least often first, nearest
    // first among equals: a part whose children keep failing gives way to the next.
    std::vector<const GoalScore::Miss*> parts;
    for (const GoalScore::Miss& miss : score.misses) parts.push_back(&miss);
    std::stable_sort(parts.begin(), parts.end(), [&](const GoalScore::Miss* a, const GoalScore::Miss* b) {
        return failures_of(world, a->part) < failures_of(world, b->part);
    });
    // Points that keep every met part first, for every part; only when none is left, those that
    // re-simulate a met part's body: where the bodies all touch (the quick start's toys tumbling
    // down one chute) no point keeps them, and a search that refused the rest would stall.
    for (RiskPass pass : {RiskPass::KeepsEveryMetPart, RiskPass::RisksFew, RiskPass::RisksMany})
        for (const GoalScore::Miss* miss : parts)
            if (choose_for(world, record, score, *miss, pass, chosen)) {
                refined_part_[world] = miss->part;
                return true;
            }
    return false;
}

uint32_t BranchPlanner::failures_of(uint64_t world, int32_t part) const {
    const auto it = failures_.find({world, part});
    return it == failures_.end() ? 0 : it->second;
}

bool BranchPlanner::choose_for(uint64_t world, const StoredWorld& record, const GoalScore& score,
                               const GoalScore::Miss& miss, RiskPass pass, Branch& chosen) {
    std::vector<size_t> lateness;
    const std::vector<Branch> points = branch_points(record, score, miss, pass, lateness);
    std::vector<size_t> bins_open;
    for (size_t k = 0; k < points.size(); ++k)
        if (!tried_.count({world, points[k]})) bins_open.push_back(lateness[k]);
    if (bins_open.empty()) return false;
    const size_t bin = choose_lateness(bins_open);
    // The bin's points, and those of them not tried yet (indices into `in_bin`).
    std::vector<size_t> in_bin, open;
    for (size_t k = 0; k < points.size(); ++k) {
        if (lateness[k] != bin) continue;
        if (!tried_.count({world, points[k]})) open.push_back(in_bin.size());
        in_bin.push_back(k);
    }
    // Where the failures point, as an index into `in_bin`: for a positive part 1, 2, 4, ... points
    // before the latest; for a negative part that many tenths of a second before it. A break is one
    // moment, and how far before it a branch must go to mend it is a time: the staircase's figure
    // touches a step every few frames, and a back-off in points stayed within 0.3 s of a break that
    // a branch 1.5 s before it mended.
    const uint32_t failures = std::min<uint32_t>(back_off_failures(world, miss.part, bin), 20);
    const double steps_back = static_cast<double>((1u << failures) - 1);
    double target = static_cast<double>(in_bin.size() - 1) - steps_back;
    if (boxes_[static_cast<size_t>(miss.part)].negative) {
        const double wanted = static_cast<double>(points[in_bin.back()].frame) - kBackOffStepS * record.record_hz * steps_back;
        size_t k = 0;
        while (k + 1 < in_bin.size() && static_cast<double>(points[in_bin[k + 1]].frame) <= wanted) ++k;
        target = static_cast<double>(k);
    }
    std::vector<double> weights;
    double total = 0;
    for (size_t k : open) {
        weights.push_back(portable::pow(0.5, std::fabs(static_cast<double>(k) - std::max(0.0, target))));
        total += weights.back();
    }
    double pick = random_.uniform01() * total;
    size_t choice = open.back();
    for (size_t i = 0; i < open.size(); ++i) {
        if (pick < weights[i]) {
            choice = open[i];
            break;
        }
        pick -= weights[i];
    }
    chosen = points[in_bin[choice]];
    tried_.insert({world, chosen});
    refined_lateness_[world] = bin;
    return true;
}

uint32_t BranchPlanner::back_off_failures(uint64_t world, int32_t part, size_t bin) const {
    if (part < 0 || !boxes_[static_cast<size_t>(part)].negative) return failures_of(world, part);
    const auto it = length_failures_.find({world, part});
    return it == length_failures_.end() ? 0 : it->second[bin];
}

size_t BranchPlanner::choose_lateness(const std::vector<size_t>& bins_open) {
    size_t best = bins_open.front();
    double best_draw = -1;
    for (size_t bin = 0; bin < kLatenessBins; ++bin) {
        if (std::find(bins_open.begin(), bins_open.end(), bin) == bins_open.end()) continue;
        const LatenessRecord& r = lateness_record_[bin];
        const double draw = beta_draw(r.gains + 1, r.refinements - r.gains + 1);
        if (draw > best_draw) {
            best_draw = draw;
            best = bin;
        }
    }
    return best;
}

double BranchPlanner::beta_draw(uint32_t a, uint32_t b) {
    // Gamma(n) for whole n is a sum of n unit exponentials; Ga / (Ga + Gb) is Beta(a, b).
    const auto gamma = [&](uint32_t n) {
        double sum = 0;
        for (uint32_t i = 0; i < n; ++i) sum -= portable::log(1.0 - random_.uniform01());
        return sum;
    };
    const double ga = gamma(a), gb = gamma(b);
    return ga / (ga + gb);
}

void BranchPlanner::note_children(uint64_t parent, double parent_value,
                                  const std::vector<std::pair<uint64_t, double>>& children, double gain) {
    const int32_t part = refined_part_.count(parent) ? refined_part_.at(parent) : -1;
    const uint32_t parent_failures = failures_of(parent, part);
    double best_child = -1;
    for (const auto& [child, value] : children) {
        best_child = std::max(best_child, value);
        // A child no better than its parent failed where the parent did: it starts backing
        // up from there instead of trying the same late branch points again.
        failures_[{child, part}] = value > parent_value + gain ? 0 : parent_failures + 1;
    }
    if (best_child > parent_value + gain) failures_[{parent, part}] = 0;
    else ++failures_[{parent, part}];
    const auto bin = refined_lateness_.find(parent);
    if (part >= 0 && boxes_[static_cast<size_t>(part)].negative && bin != refined_lateness_.end()) {
        std::array<uint32_t, kLatenessBins>& own = length_failures_[{parent, part}];
        const std::array<uint32_t, kLatenessBins> before = own;
        for (const auto& [child, value] : children) {
            std::array<uint32_t, kLatenessBins>& lengths = length_failures_[{child, part}];
            lengths = before;
            if (value > parent_value + gain) lengths.fill(0);
            else ++lengths[bin->second];
        }
        if (best_child > parent_value + gain) own.fill(0);
        else ++own[bin->second];
    }
    // Whether branching this late paid: a child met a part more than its parent.
    if (bin != refined_lateness_.end()) {
        LatenessRecord& record = lateness_record_[bin->second];
        ++record.refinements;
        if (std::floor(best_child) > std::floor(parent_value)) ++record.gains;
    }
}

}  // namespace mwb
