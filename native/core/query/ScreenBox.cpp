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

void check_goal(const std::vector<QueryBox>& boxes) {
    if (boxes.empty()) throw std::invalid_argument("the goal has no boxes: a goal needs at least one box");
    goal_order(boxes);
}

}  // namespace mwb
