#include "query/ScreenBox.h"

#include <stdexcept>
#include <string>

#include "query/GoalScore.h"

namespace mwb {

QueryBox make_query_box(const ScreenBoxSpec& spec) {
    QueryBox box;
    try {
        box.frustum = make_screen_frustum(spec.view, spec.projection, spec.viewport_width, spec.viewport_height,
                                          spec.rect[0], spec.rect[1], spec.rect[2], spec.rect[3]);
    } catch (const std::invalid_argument& error) {
        throw std::invalid_argument(std::string("has an unusable rectangle or camera: ") + error.what());
    }
    if (spec.bodies.empty()) throw std::invalid_argument("tests no bodies: a box needs at least one body");
    if (spec.time_window) {
        if (!(spec.time_window->first <= spec.time_window->second))
            throw std::invalid_argument("has a time window (time_window) that ends before it starts");
        box.window = {spec.time_window->first, spec.time_window->second};
    }
    if (spec.after < -1) throw std::invalid_argument("is to be met after a box at a position below 0");
    box.negative = spec.negative;
    box.swept = spec.swept;
    box.bodies = spec.bodies;
    box.after = spec.after;
    return box;
}

QueryBox make_orientation_part(const OrientationPartSpec& spec) {
    QueryBox part;
    if (spec.bodies.empty()) throw std::invalid_argument("tests no bodies: an orientation part needs at least one body");
    if (!(spec.within_deg > 0 && spec.within_deg < 180))
        throw std::invalid_argument("has a tolerance (within_deg) outside 0 to 180 degrees");
    if (!(norm(spec.axis) > 1e-9) || !(norm(spec.target) > 1e-9))
        throw std::invalid_argument("has a zero direction: axis and target must be non-zero vectors");
    if (!(spec.longer_than_s >= 0)) throw std::invalid_argument("has a negative duration (longer_than_s)");
    if (spec.time_window) {
        if (!(spec.time_window->first <= spec.time_window->second))
            throw std::invalid_argument("has a time window (time_window) that ends before it starts");
        part.window = {spec.time_window->first, spec.time_window->second};
    }
    if (spec.after < -1) throw std::invalid_argument("is to be met after a box at a position below 0");
    OrientationTest test;
    test.axis = scale(spec.axis, 1 / norm(spec.axis));
    test.target = scale(spec.target, 1 / norm(spec.target));
    test.within_rad = spec.within_deg * (3.14159265358979323846 / 180);
    test.longer_than_s = spec.longer_than_s;
    part.orientation = test;
    part.negative = spec.negative;
    part.bodies = spec.bodies;
    part.after = spec.after;
    return part;
}

void check_goal(const std::vector<QueryBox>& boxes) {
    if (boxes.empty()) throw std::invalid_argument("the goal has no parts: a goal needs at least one box or pose part");
    goal_order(boxes);
}

}  // namespace mwb
