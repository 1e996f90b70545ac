#pragma once
// A goal is a list of query boxes (and orientation parts), some of which must be met after
// another. How far a world's paths get towards it: the parts met, counted along the order, and
// how close it comes to the first part it misses. The browser's ordered queries and the goal
// search both use this.
#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "common/Math.h"
#include "query/PathTree.h"

namespace mwb {

struct QueryBox;

/// Per scene body, its rotation at each of its path's points (empty for bodies no orientation
/// part names); the orientation parts of a goal read these.
using BodyOrientations = std::vector<std::vector<Quat>>;

/// The boxes in the order they are met: every box after the one it must follow, otherwise in list
/// order. Throws std::invalid_argument for an `after` that names no other box or an ordering cycle.
std::vector<size_t> goal_order(const std::vector<QueryBox>& boxes);
/// The same for the parts' `after`s alone (afters[k]: the position of the part that part k is met
/// after, -1: none): the one rule the add-on's After menu asks, offering no order that closes a
/// cycle.
std::vector<size_t> goal_order(const std::vector<int32_t>& afters);

struct GoalScore {
    /// Parts met (boxes and orientation parts); an ordered part counts only when the part before it
    /// is met and it is met after it.
    uint32_t boxes_met = 0;
    std::vector<uint8_t> met;          ///< per box
    std::vector<double> met_time_s;    ///< per met box: when (a negative box: when its window opened)
    /// The part to meet next, or -1 when all are met: of the unmet parts whose predecessor is met,
    /// the one the world comes nearest to (the highest closeness; the first in goal order on a
    /// tie). Without closeness: the first unmet part in goal order.
    int32_t first_unmet = -1;
    /// How near the world came to that part, in [0, 1): a positive box 1 / (1 + d), d the least
    /// view_relative_distance of its bodies' paths within its window; a negative box the share of
    /// its window that no body spends inside; a positive orientation part 1 / (1 + e), e the
    /// worst excess of 1 - cos(angle) over its tolerance's, in tolerances; a negative one the
    /// share of its window no body spends within. Over several bodies, a positive orientation
    /// part averages each body's 1 / (1 + e) (1 for a body within), a negative one each body's
    /// share of the window out of the pose (1 for a body not held too long). For a part met after
    /// another, a quarter of it is instead the time left to meet it when that one was met, as a
    /// share of its deadline (the window's end, or the paths' end): a slow leader gives way to a
    /// quicker world that met as many parts. 0 when every part is met. For a world that broke a negative part (violation_time_s finite), instead how late it
    /// broke: that time as a share of its paths' length (then, for a pose part, to a thousandth,
    /// plus a thousandth of violation_closeness).
    double closeness = 0;
    /// Where the first unmet box went wrong (seconds): for a positive box the first moment the
    /// nearest body was already about as near (within 5% + 0.02 box sizes) as it came in the
    /// window; for a negative box the first entry; for a positive orientation part the start of
    /// the turn that ended at its worst moment; for a negative one when a body began the stay
    /// that was too long (before the window opened if it lay so since then). And the bodies to
    /// blame: the one that came nearest, those that entered (or stayed within), earliest first,
    /// or those out of tolerance, worst first.
    double failure_time_s = 0;
    std::vector<uint32_t> failing_bodies;
    /// When that box's window opens, after the box it follows (seconds; 0 for the whole path).
    double window_start_s = 0;
    /// For a positive box with a time window: when one of its bodies was already in it before
    /// the window opened (after the box it follows was met) and went on, the world being too
    /// soon there. Infinity when none was.
    double early_visit_s = std::numeric_limits<double>::infinity();

    /// Every part it could meet next, as above for first_unmet (closeness, where it went wrong,
    /// the bodies to blame), nearest first; the first is first_unmet's. Empty without closeness.
    struct Miss {
        int32_t part = -1;
        double closeness = 0, failure_time_s = 0, window_start_s = 0;
        std::vector<uint32_t> failing_bodies;
        double early_visit_s = std::numeric_limits<double>::infinity();
    };
    std::vector<Miss> misses;

    /// When the world first entered a negative part it misses (a box, or a pose held too long):
    /// from then on it cannot meet the goal, whatever it meets later. Infinity when it misses no
    /// negative part. Only with closeness.
    double violation_time_s = std::numeric_limits<double>::infinity();
    /// The parts met before that moment: the negative ones it meets, and the positive ones decided
    /// before it (a box when first met, an orientation part when its window closes). A search
    /// mending the violation branches before it and re-runs what came after, so only these can be
    /// kept. Poses waiting on a missed box (waits_on_missed_box) are left out. boxes_met when no
    /// negative part is missed and no pose waits.
    uint32_t parts_before_violation = 0;
    /// Of those, the positive ones: what a refinement mending the violation can keep and a fresh
    /// world cannot.
    uint32_t positive_parts_before_violation = 0;
    /// When that negative part is a pose part: how near it was to being kept (its closeness: the
    /// share of the window each body spent out of the pose, averaged), which tells apart worlds
    /// that broke it at the same moment. 0 otherwise.
    double violation_closeness = 0;

    /// Orders worlds for a search: more parts met before the first violation, then closer to the
    /// next part. A tumble that goes all the way down after an arm poked out at the top counts no
    /// more than what it did before poking out.
    double value() const { return parts_before_violation + closeness; }

    /// What tells two worlds apart for a search: the value to a thousandth of a part, when the
    /// first negative part was entered, to a millisecond, and violation_closeness to a thousandth.
    /// Worlds with the same key are for the goal the same world; refining both would repeat work.
    std::array<long long, 3> search_key() const;
};

/// Whether part `part`, met or not, is a positive pose part sharing a body with a positive box the
/// world misses over an overlapping window (a letter upright beside the slot it must end in). Such
/// a pose counts towards the world's value only once the box is met, it is not the part to meet
/// next while the box is missed, and a search need not keep it: the refinement that takes the body
/// to its box re-runs its pose.
bool waits_on_missed_box(const std::vector<QueryBox>& boxes, const GoalScore& score, size_t part);

/// Scores one world given its body paths (one PathView per scene body, empty for bodies it lacks)
/// and each body's bounding radius (for swept boxes). `order` is goal_order(boxes). Without
/// `with_closeness` only the met flags, times and count are computed (what a query needs).
/// `orientations` is needed when a part tests orientation (std::invalid_argument without it).
GoalScore score_goal(const std::vector<PathView>& paths, const std::vector<double>& body_radii_m,
                     const std::vector<QueryBox>& boxes, const std::vector<size_t>& order,
                     bool with_closeness = true, const BodyOrientations* orientations = nullptr);

}  // namespace mwb
