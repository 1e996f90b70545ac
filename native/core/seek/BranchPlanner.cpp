#include "seek/BranchPlanner.h"

#include <algorithm>
#include <cmath>

#include "common/PortableMath.h"

namespace mwb {
namespace {

// Branch points just before a box's window opens, seconds.
constexpr double kBeforeWindow[] = {0.1, 0.25, 0.5, 1.0, 2.0};
// Spacing of the fallback branch points when nothing collided in the span, seconds.
constexpr double kGridSpacing = 0.5;
// Negative boxes entered by many bodies: the earliest few are refined.
constexpr size_t kMaxFailingBodies = 8;

// When the last of `bodies` came to rest for good (the world's end if one never did).
double rest_time(const StoredWorld& w, const std::vector<uint32_t>& bodies) {
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

std::vector<Branch> BranchPlanner::branch_points(const StoredWorld& w, const GoalScore& score) const {
    const QueryBox& box = boxes_[static_cast<size_t>(score.first_unmet)];
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
    }
    double upper = std::min(score.failure_time_s, world_end);
    if (!(upper > lower)) upper = world_end;
    std::vector<uint32_t> failing;
    for (uint32_t b : score.failing_bodies)
        if (simulated(b) && failing.size() < kMaxFailingBodies) failing.push_back(b);
    if (failing.empty())
        for (uint32_t b : box.bodies)
            if (simulated(b) && failing.size() < kMaxFailingBodies) failing.push_back(b);
    if (failing.empty()) return {};
    // Branching after the bodies came to rest changes nothing (unless something hits them).
    const double rest = rest_time(w, failing);
    if (rest + 1 / hz < upper) upper = rest + 1 / hz;
    if (!(upper > lower)) upper = world_end;

    std::set<Branch> points;
    auto add = [&](double t, std::vector<uint32_t> bodies) {
        if (!(t >= lower && t < upper)) return;
        std::sort(bodies.begin(), bodies.end());
        bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
        points.insert({static_cast<uint64_t>(std::floor(t * hz)), std::move(bodies)});
    };
    // The bodies that missed, with everything jointed to them: an arm's impact turns the body.
    const std::set<uint32_t> failing_set = jointed_with(failing);
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
    const double opens = box.window.empty() ? upper : std::max(box.window.lo_s, score.window_start_s);
    for (double before : kBeforeWindow) add(opens - before, failing);
    if (points.size() < 4)
        for (double t = lower; t < upper; t += kGridSpacing) add(t, failing);
    return {points.begin(), points.end()};
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
    std::vector<Branch> points = branch_points(record, score);
    std::vector<size_t> open;
    for (size_t k = 0; k < points.size(); ++k)
        if (!tried_.count({world, points[k]})) open.push_back(k);
    if (open.empty()) return false;
    const uint32_t failures = std::min<uint32_t>(failures_[world], 20);
    const double target = static_cast<double>(points.size() - 1) - static_cast<double>((1u << failures) - 1);
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
    chosen = points[choice];
    tried_.insert({world, chosen});
    return true;
}

void BranchPlanner::note_children(uint64_t parent, double parent_value,
                                  const std::vector<std::pair<uint64_t, double>>& children, double gain) {
    const uint32_t parent_failures = failures_[parent];
    double best_child = -1;
    for (const auto& [child, value] : children) {
        best_child = std::max(best_child, value);
        // A child no better than its parent failed where the parent did: it starts backing
        // up from there instead of trying the same late branch points again.
        failures_[child] = value > parent_value + gain ? 0 : parent_failures + 1;
    }
    if (best_child > parent_value + gain) failures_[parent] = 0;
    else ++failures_[parent];
}

}  // namespace mwb
