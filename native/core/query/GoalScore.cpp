#include "query/GoalScore.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "query/PathIndex.h"

namespace mwb {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Closeness stays below 1 so that meeting a box always counts for more than nearly meeting it.
constexpr double kMaxCloseness = 0.999;

bool has_path(const std::vector<PathView>& paths, uint32_t body) {
    return body < paths.size() && paths[body].point_count() > 0;
}

double radius_of(const QueryBox& box, const std::vector<double>& radii, uint32_t body) {
    return box.swept && body < radii.size() ? radii[body] : 0.0;
}

// Indices of the path's samples within [lo, hi], plus the held last pose when the hold reaches
// into the window (the last point again).
template <typename Visit>
void visit_samples(const PathView& path, double lo, double hi, Visit&& visit) {
    const size_t n = path.point_count();
    for (size_t k = 0; k < n; ++k) {
        const double t = path.time_of(k);
        if (t >= lo && t <= hi) visit(k, t);
    }
    const double last = path.time_of(n - 1);
    if (last < lo && path.end_time_s() >= lo) visit(n - 1, lo);
}

void score_positive_miss(const std::vector<PathView>& paths, const std::vector<double>& radii, const QueryBox& box,
                         double lo, double hi, GoalScore& score) {
    double nearest = kInfinity;
    uint32_t nearest_body = 0;
    for (uint32_t body : box.bodies) {
        if (!has_path(paths, body)) continue;
        const PathView& path = paths[body];
        const double radius = radius_of(box, radii, body);
        visit_samples(path, lo, hi, [&](size_t k, double) {
            const double d = box.frustum.view_relative_distance(path.point(k), radius);
            if (d < nearest) {
                nearest = d;
                nearest_body = body;
            }
        });
    }
    if (!std::isfinite(nearest)) {
        score.failure_time_s = std::max(lo, 0.0);
        return;
    }
    score.closeness = std::min(kMaxCloseness, 1 / (1 + nearest));
    score.failing_bodies = {nearest_body};
    // Where it went wrong: the first moment the body was already about as near as it ever got in
    // the window (a body that stopped short at 3 s failed then, not when the window opened).
    const PathView& path = paths[nearest_body];
    const double radius = radius_of(box, radii, nearest_body);
    const double near_enough = nearest * 1.05 + 0.02;
    for (size_t k = 0; k < path.point_count() && path.time_of(k) <= hi; ++k)
        if (box.frustum.view_relative_distance(path.point(k), radius) <= near_enough) {
            score.failure_time_s = path.time_of(k);
            return;
        }
    score.failure_time_s = std::max(lo, 0.0);
}

void score_negative_miss(const std::vector<PathView>& paths, const std::vector<double>& radii, const QueryBox& box,
                         double lo, double hi, GoalScore& score) {
    // Share of the window's samples at which some body is inside (all bodies share one clock).
    std::vector<std::pair<double, uint32_t>> entries;
    size_t samples = 0, inside = 0;
    std::vector<double> inside_times;
    for (uint32_t body : box.bodies) {
        if (!has_path(paths, body)) continue;
        const PathView& path = paths[body];
        const double radius = radius_of(box, radii, body);
        const double entry = path.first_touch_time(box.frustum, {lo, hi}, radius);
        if (entry >= 0) entries.emplace_back(entry, body);
        size_t body_samples = 0;
        visit_samples(path, lo, hi, [&](size_t k, double t) {
            ++body_samples;
            if (box.frustum.touches_segment(path.point(k), path.point(k), 0, 1, radius)) inside_times.push_back(t);
        });
        samples = std::max(samples, body_samples);
    }
    std::sort(inside_times.begin(), inside_times.end());
    inside = static_cast<size_t>(std::unique(inside_times.begin(), inside_times.end()) - inside_times.begin());
    const double share_inside = samples > 0 ? std::min(1.0, double(inside) / double(samples)) : 1.0;
    score.closeness = std::min(kMaxCloseness, 1 - share_inside);
    std::sort(entries.begin(), entries.end());
    score.failure_time_s = entries.empty() ? lo : entries.front().first;
    for (const auto& [t, body] : entries) score.failing_bodies.push_back(body);
}

}  // namespace

std::vector<size_t> goal_order(const std::vector<QueryBox>& boxes) {
    const size_t n = boxes.size();
    for (size_t k = 0; k < n; ++k)
        if (boxes[k].after >= 0 && (static_cast<size_t>(boxes[k].after) >= n || static_cast<size_t>(boxes[k].after) == k))
            throw std::invalid_argument(
                static_cast<size_t>(boxes[k].after) == k
                    ? "box " + std::to_string(k + 1) + " is to be met after itself"
                    : "box " + std::to_string(k + 1) + " is to be met after box " + std::to_string(boxes[k].after + 1) +
                          ", but the goal has " + std::to_string(n) + " boxes");
    // Each box has at most one predecessor: the order is a forest. Walk it depth first, roots in
    // list order, children in list order, so the order is the list's wherever the list allows.
    std::vector<size_t> order;
    std::vector<uint8_t> placed(n, 0);
    std::vector<size_t> stack;
    for (size_t root = 0; root < n; ++root) {
        if (boxes[root].after >= 0) continue;
        stack.push_back(root);
        while (!stack.empty()) {
            const size_t k = stack.back();
            stack.pop_back();
            placed[k] = 1;
            order.push_back(k);
            for (size_t c = n; c-- > 0;)
                if (boxes[c].after == static_cast<int32_t>(k)) stack.push_back(c);
        }
    }
    for (size_t k = 0; k < n; ++k)
        if (!placed[k]) throw std::invalid_argument("the boxes' order has a cycle through box " + std::to_string(k + 1));
    return order;
}

GoalScore score_goal(const std::vector<PathView>& paths, const std::vector<double>& body_radii_m,
                     const std::vector<QueryBox>& boxes, const std::vector<size_t>& order, bool with_closeness) {
    GoalScore score;
    score.met.assign(boxes.size(), 0);
    score.met_time_s.assign(boxes.size(), 0);
    for (size_t k : order) {
        const QueryBox& box = boxes[k];
        double lo = box.window.empty() ? -kInfinity : box.window.lo_s;
        const double hi = box.window.empty() ? kInfinity : box.window.hi_s;
        bool reachable = true;
        if (box.after >= 0) {
            const auto before = static_cast<size_t>(box.after);
            reachable = score.met[before] != 0;
            lo = std::max(lo, score.met_time_s[before]);
        }
        bool met = false;
        double when = kInfinity;
        if (reachable && lo <= hi) {
            for (uint32_t body : box.bodies) {
                if (body >= body_radii_m.size()) throw std::out_of_range("query box names body " + std::to_string(body));
                if (!has_path(paths, body)) continue;
                const double t = paths[body].first_touch_time(box.frustum, {lo, hi}, radius_of(box, body_radii_m, body));
                if (t >= 0) when = std::min(when, t);
            }
            met = box.negative ? !std::isfinite(when) : std::isfinite(when);
        }
        if (met) {
            score.met[k] = 1;
            score.met_time_s[k] = box.negative ? std::max(lo, 0.0) : when;
            ++score.boxes_met;
        } else if (score.first_unmet < 0) {
            score.first_unmet = static_cast<int32_t>(k);
            score.window_start_s = std::max(lo, 0.0);
            // A box whose predecessor is unmet cannot come first: its predecessor is earlier in order.
            if (with_closeness) {
                if (box.negative) score_negative_miss(paths, body_radii_m, box, lo, hi, score);
                else score_positive_miss(paths, body_radii_m, box, lo, hi, score);
            }
        }
    }
    return score;
}

}  // namespace mwb
