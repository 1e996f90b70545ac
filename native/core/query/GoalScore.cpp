#include "query/GoalScore.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/PortableMath.h"
#include "query/PathIndex.h"

namespace mwb {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Closeness stays below 1 so that meeting a box always counts for more than nearly meeting it.
constexpr double kMaxCloseness = 0.999;
// The share of the closeness to an ordered part that is the time left to meet it (see score_goal).
constexpr double kSpareWeight = 0.25;

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

// The first moment from `since` until its window opens that one of a positive box's bodies is in
// it (infinity if none is).
double early_visit(const std::vector<PathView>& paths, const std::vector<double>& radii, const QueryBox& box,
                   double since) {
    double first = kInfinity;
    if (!(since < box.window.lo_s)) return first;
    for (uint32_t body : box.bodies) {
        if (!has_path(paths, body)) continue;
        const double t = paths[body].first_touch_time(box.frustum, {since, box.window.lo_s}, radius_of(box, radii, body));
        if (t >= 0) first = std::min(first, t);
    }
    return first;
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

// --- orientation parts ---------------------------------------------------------------------

// cos of the angle between the body's axis, turned by `rotation`, and the target.
double alignment(const OrientationTest& test, const Quat& rotation) {
    return dot(quat_rotate(rotation, test.axis), test.target);
}

const std::vector<Quat>& rotations_of(const BodyOrientations& orientations, const PathView& path, uint32_t body) {
    if (body >= orientations.size() || orientations[body].size() != path.point_count())
        throw std::invalid_argument("orientation part: body " + std::to_string(body) + " has no rotations at its path's points");
    return orientations[body];
}

// One body's stretches within the tolerance during [lo, hi]: (start, end) seconds; a stretch
// that reaches the path's last point lasts while that pose is held.
std::vector<std::pair<double, double>> stretches_within(const PathView& path, const std::vector<Quat>& rotations,
                                                        const OrientationTest& test, double lo, double hi) {
    const double tolerance = portable::cos(test.within_rad);
    std::vector<std::pair<double, double>> stretches;
    bool open = false;
    const size_t last = path.point_count() - 1;
    visit_samples(path, lo, hi, [&](size_t k, double t) {
        const bool within = alignment(test, rotations[k]) >= tolerance;
        if (within && !open) stretches.emplace_back(t, t);
        if (within) stretches.back().second = k == last ? std::min(hi, path.end_time_s()) : t;
        open = within;
    });
    return stretches;
}

bool stays_too_long(const std::pair<double, double>& stretch, const OrientationTest& test) {
    return test.longer_than_s > 0 ? stretch.second - stretch.first > test.longer_than_s : true;
}

// When a body's stretch within the pose that is in the window at `from` began: it may have lain
// so since before the window opened (a die that came to rest on the wrong face at 1 s failed
// then, not when the last second began).
double stretch_start(const PathView& path, const std::vector<Quat>& rotations, const OrientationTest& test, double from) {
    const double tolerance = portable::cos(test.within_rad);
    size_t k = 0;
    while (k + 1 < path.point_count() && path.time_of(k + 1) <= from) ++k;
    if (path.time_of(k) > from || alignment(test, rotations[k]) < tolerance) return from;
    while (k > 0 && alignment(test, rotations[k - 1]) >= tolerance) --k;
    return std::min(from, path.time_of(k));
}

// Whether the part is met, and when it failed (for the closeness and branch points).
bool orientation_met(const std::vector<PathView>& paths, const BodyOrientations& orientations, const QueryBox& part,
                     double lo, double hi) {
    const OrientationTest& test = *part.orientation;
    const double tolerance = portable::cos(test.within_rad);
    bool any_sample = false;
    for (uint32_t body : part.bodies) {
        if (!has_path(paths, body)) continue;
        const std::vector<Quat>& rotations = rotations_of(orientations, paths[body], body);
        if (part.negative) {
            for (const auto& stretch : stretches_within(paths[body], rotations, test, lo, hi))
                if (stays_too_long(stretch, test)) return false;
            continue;
        }
        bool out = false;
        visit_samples(paths[body], lo, hi, [&](size_t k, double) {
            any_sample = true;
            out = out || alignment(test, rotations[k]) < tolerance;
        });
        if (out) return false;
    }
    return part.negative || any_sample;
}

void score_orientation_miss(const std::vector<PathView>& paths, const BodyOrientations& orientations,
                            const QueryBox& part, double lo, double hi, GoalScore& score) {
    const OrientationTest& test = *part.orientation;
    const double tolerance = portable::cos(test.within_rad);
    if (part.negative) {
        // Per body, the share of the window's samples it spends out of the pose when it stays in
        // too long (1 for a body that does not): one body lying on its back is nearer to the goal
        // than eight, so a search has a slope to climb.
        std::vector<std::pair<double, uint32_t>> offences;
        double sum = 0;
        size_t counted = 0;
        for (uint32_t body : part.bodies) {
            if (!has_path(paths, body)) continue;
            const std::vector<Quat>& rotations = rotations_of(orientations, paths[body], body);
            bool offends = false;
            for (const auto& stretch : stretches_within(paths[body], rotations, test, lo, hi))
                if (stays_too_long(stretch, test)) {
                    offences.emplace_back(stretch_start(paths[body], rotations, test, stretch.first), body);
                    offends = true;
                    break;
                }
            size_t samples = 0, within = 0;
            visit_samples(paths[body], lo, hi, [&](size_t k, double) {
                ++samples;
                within += alignment(test, rotations[k]) >= tolerance;
            });
            if (samples == 0) continue;
            sum += offends ? 1 - double(within) / double(samples) : 1.0;
            ++counted;
        }
        score.closeness = counted > 0 ? std::min(kMaxCloseness, sum / double(counted)) : 0.0;
        std::sort(offences.begin(), offences.end());
        score.failure_time_s = offences.empty() ? std::max(lo, 0.0) : offences.front().first;
        for (const auto& [t, body] : offences) score.failing_bodies.push_back(body);
        return;
    }
    // Positive: how far past its tolerance the worst body turned, in tolerances (1 - cos).
    const double allowed = std::max(1e-12, 1 - tolerance);
    std::vector<std::pair<double, uint32_t>> excesses;  // (-worst excess, body)
    double worst = -1;
    uint32_t worst_body = 0;
    size_t worst_point = 0;
    for (uint32_t body : part.bodies) {
        if (!has_path(paths, body)) continue;
        const std::vector<Quat>& rotations = rotations_of(orientations, paths[body], body);
        double body_worst = 0;
        size_t body_point = 0;
        visit_samples(paths[body], lo, hi, [&](size_t k, double) {
            const double excess = (tolerance - alignment(test, rotations[k])) / allowed;
            if (excess > body_worst) {
                body_worst = excess;
                body_point = k;
            }
        });
        if (body_worst <= 0) continue;
        excesses.emplace_back(-body_worst, body);
        if (body_worst > worst) {
            worst = body_worst;
            worst_body = body;
            worst_point = body_point;
        }
    }
    if (excesses.empty()) {  // no body has a pose in the window
        score.failure_time_s = std::max(lo, 0.0);
        return;
    }
    // Each body held counts 1, each other 1 / (1 + its worst excess): one die off its face is
    // nearer to the goal than five, so a search has a slope to climb.
    double sum = 0;
    size_t counted = 0;
    for (uint32_t body : part.bodies)
        if (has_path(paths, body)) {
            const auto it = std::find_if(excesses.begin(), excesses.end(), [body](const auto& e) { return e.second == body; });
            sum += it == excesses.end() ? 1.0 : 1 / (1 - it->first);
            ++counted;
        }
    score.closeness = std::min(kMaxCloseness, sum / double(counted));
    std::sort(excesses.begin(), excesses.end());
    for (const auto& [e, body] : excesses) score.failing_bodies.push_back(body);
    // It went wrong where the worst body last turned out of tolerance before its worst moment.
    const std::vector<Quat>& rotations = orientations[worst_body];
    size_t k = worst_point;
    while (k > 0 && alignment(test, rotations[k - 1]) < tolerance) --k;
    score.failure_time_s = paths[worst_body].time_of(k);
}

// Whether a positive pose part holds only on condition that positive box `box` is met: they share
// a body and their windows overlap. Until the box is met that body has still to get there, and the
// refinement that takes it there re-runs its pose as well: a letter upright beside its slot is no
// nearer to "upright in its slot" than one lying beside it.
bool pose_waits_on(const QueryBox& pose, const QueryBox& box) {
    if (!pose.orientation || pose.negative || box.orientation || box.negative) return false;
    const bool overlap = pose.window.empty() || box.window.empty() ||
                         (pose.window.lo_s <= box.window.hi_s && box.window.lo_s <= pose.window.hi_s);
    if (!overlap) return false;
    for (uint32_t body : pose.bodies)
        if (std::find(box.bodies.begin(), box.bodies.end(), body) != box.bodies.end()) return true;
    return false;
}

}  // namespace

bool waits_on_missed_box(const std::vector<QueryBox>& boxes, const GoalScore& score, size_t part) {
    for (size_t j = 0; j < boxes.size(); ++j)
        if (j < score.met.size() && !score.met[j] && pose_waits_on(boxes[part], boxes[j])) return true;
    return false;
}

std::array<long long, 3> GoalScore::search_key() const {
    const long long violated = std::isfinite(violation_time_s) ? std::llround(violation_time_s * 1000)
                                                               : std::numeric_limits<long long>::max();
    return {std::llround(value() * 1000), violated, std::llround(violation_closeness * 1000)};
}

std::vector<size_t> goal_order(const std::vector<int32_t>& afters) {
    const size_t n = afters.size();
    for (size_t k = 0; k < n; ++k)
        if (afters[k] >= 0 && (static_cast<size_t>(afters[k]) >= n || static_cast<size_t>(afters[k]) == k))
            throw std::invalid_argument(
                static_cast<size_t>(afters[k]) == k
                    ? "part " + std::to_string(k + 1) + " is to be met after itself"
                    : "part " + std::to_string(k + 1) + " is to be met after part " + std::to_string(afters[k] + 1) +
                          ", but the goal has " + std::to_string(n) + (n == 1 ? " part" : " parts"));
    // Each box has at most one predecessor: the order is a forest. Walk it depth first, roots in
    // list order, children in list order, so the order is the list's wherever the list allows.
    std::vector<size_t> order;
    std::vector<uint8_t> placed(n, 0);
    std::vector<size_t> stack;
    for (size_t root = 0; root < n; ++root) {
        if (afters[root] >= 0) continue;
        stack.push_back(root);
        while (!stack.empty()) {
            const size_t k = stack.back();
            stack.pop_back();
            placed[k] = 1;
            order.push_back(k);
            for (size_t c = n; c-- > 0;)
                if (afters[c] == static_cast<int32_t>(k)) stack.push_back(c);
        }
    }
    for (size_t k = 0; k < n; ++k)
        if (!placed[k]) throw std::invalid_argument("the parts' order has a cycle through part " + std::to_string(k + 1));
    return order;
}

std::vector<size_t> goal_order(const std::vector<QueryBox>& boxes) {
    std::vector<int32_t> afters;
    for (const QueryBox& box : boxes) afters.push_back(box.after);
    return goal_order(afters);
}

GoalScore score_goal(const std::vector<PathView>& paths, const std::vector<double>& body_radii_m,
                     const std::vector<QueryBox>& boxes, const std::vector<size_t>& order, bool with_closeness,
                     const BodyOrientations* orientations) {
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
        if (box.orientation) {
            if (!orientations) throw std::invalid_argument("part " + std::to_string(k + 1) + " tests orientation: give the rotations");
            met = reachable && lo <= hi && orientation_met(paths, *orientations, box, lo, hi);
        } else if (reachable && lo <= hi) {
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
            score.met_time_s[k] = box.negative || box.orientation ? std::max(lo, 0.0) : when;
            ++score.boxes_met;
        } else if (!with_closeness) {
            if (score.first_unmet < 0) score.first_unmet = static_cast<int32_t>(k);
        } else if (reachable) {
            // Each part it could meet next and how near it comes; the nearest is first_unmet: a
            // search works on what is closest to done (the letter one bounce from its slot before
            // the one across the board), and the score rises with every part it brings nearer.
            GoalScore miss;
            miss.window_start_s = std::max(lo, 0.0);
            if (box.orientation) score_orientation_miss(paths, *orientations, box, lo, hi, miss);
            else if (box.negative) score_negative_miss(paths, body_radii_m, box, lo, hi, miss);
            else {
                score_positive_miss(paths, body_radii_m, box, lo, hi, miss);
                if (!box.window.empty() && reachable) {
                    const double since = box.after >= 0 ? score.met_time_s[static_cast<size_t>(box.after)] : 0.0;
                    miss.early_visit_s = early_visit(paths, body_radii_m, box, since);
                }
            }
            score.misses.push_back({static_cast<int32_t>(k), miss.closeness, miss.failure_time_s, miss.window_start_s,
                                    std::move(miss.failing_bodies), miss.early_visit_s});
        }
    }
    // A pose waiting on a missed box is worked on once the box is met: refined for its pose now, the
    // body would be refined again for its box, and that re-runs the pose.
    const auto waiting = [&](const GoalScore::Miss& miss) {
        return waits_on_missed_box(boxes, score, static_cast<size_t>(miss.part));
    };
    if (!std::all_of(score.misses.begin(), score.misses.end(), waiting))
        score.misses.erase(std::remove_if(score.misses.begin(), score.misses.end(), waiting), score.misses.end());
    // Nearest first; on a tie the first in goal order (the sort is stable).
    std::stable_sort(score.misses.begin(), score.misses.end(),
                     [](const GoalScore::Miss& a, const GoalScore::Miss& b) { return a.closeness > b.closeness; });
    if (!score.misses.empty()) {
        const GoalScore::Miss& nearest = score.misses.front();
        score.first_unmet = nearest.part;
        score.closeness = nearest.closeness;
        score.failure_time_s = nearest.failure_time_s;
        score.failing_bodies = nearest.failing_bodies;
        score.window_start_s = nearest.window_start_s;
        score.early_visit_s = nearest.early_visit_s;
    }
    const GoalScore::Miss* violated = nullptr;
    for (const GoalScore::Miss& miss : score.misses)
        if (boxes[static_cast<size_t>(miss.part)].negative && miss.failure_time_s < score.violation_time_s) {
            score.violation_time_s = miss.failure_time_s;
            violated = &miss;
        }
    // A pose held too long is a state, not an event: worlds in which some of the bodies lie wrong
    // when the window opens all break it then, and only how many of them do tells them apart.
    if (violated && boxes[static_cast<size_t>(violated->part)].orientation) score.violation_closeness = violated->closeness;
    for (size_t k = 0; k < boxes.size(); ++k) {
        if (!score.met[k]) continue;
        const QueryBox& box = boxes[k];
        const double decided = box.negative         ? -kInfinity
                               : box.orientation    ? (box.window.empty() ? kInfinity : box.window.hi_s)
                                                    : score.met_time_s[k];
        // A pose held beside its box is not yet worth a part (pose_waits_on).
        if (decided < score.violation_time_s && !waits_on_missed_box(boxes, score, k)) {
            ++score.parts_before_violation;
            if (!box.negative) ++score.positive_parts_before_violation;
        }
    }
    if (!with_closeness) return score;
    double horizon = 0;
    for (const PathView& path : paths)
        if (path.point_count() > 0) horizon = std::max(horizon, path.end_time_s());
    if (score.first_unmet >= 0 && kSpareWeight > 0) {
        // Time to spare: of two worlds that met as many parts, the one that met the last of them
        // sooner has more time left for the next, so a slow leader gives way to a quicker one.
        const QueryBox& next = boxes[static_cast<size_t>(score.first_unmet)];
        const double deadline = next.window.empty() ? horizon : std::min(horizon, next.window.hi_s);
        if (next.after >= 0 && deadline > 0) {
            const double since = score.met_time_s[static_cast<size_t>(next.after)];
            const double spare = std::clamp((deadline - since) / deadline, 0.0, 1.0);
            score.closeness = (1 - kSpareWeight) * score.closeness + kSpareWeight * kMaxCloseness * spare;
        }
    }
    if (std::isfinite(score.violation_time_s)) {
        // Past the violation nothing counts, so how near it came to a part says nothing either:
        // what a broken world has is the time it stayed clean, and a child that breaks later
        // has kept more of the goal's way (the staircase's sampled worlds mostly poke an arm out
        // within 1.5 s of 40; the share of the window spent outside told them apart by a few
        // frames and kept the search refining them).
        score.closeness = horizon > 0 ? std::clamp(score.violation_time_s / horizon, 0.0, kMaxCloseness) : 0.0;
        // Within a thousandth of the paths' length (what a search tells apart), the pose part
        // broken by fewer bodies is nearer.
        if (score.violation_closeness > 0)
            score.closeness = std::min(kMaxCloseness, (std::floor(score.closeness * 1000) + score.violation_closeness) / 1000);
    }
    return score;
}

}  // namespace mwb
