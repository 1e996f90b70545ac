#pragma once
// A box as a person draws it, and the one place that decides whether it and a goal of such boxes
// make sense: the module's QueryBox, the goal file the engine reads, and the add-on's goal writer
// all go through here, so each refuses the same boxes with the same words.
#include <array>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "query/Frustum.h"
#include "query/PathIndex.h"

namespace mwb {

struct ScreenBoxSpec {
    Matrix4 view{};        ///< row-major, world to camera
    Matrix4 projection{};  ///< row-major, camera to clip (OpenGL)
    double viewport_width = 0, viewport_height = 0;  ///< pixels
    std::array<double, 4> rect{};  ///< x0, y0, x1, y1 in pixels from the viewport's bottom-left
    bool negative = false;
    bool swept = false;
    std::vector<uint32_t> bodies;
    std::optional<std::pair<double, double>> time_window;  ///< seconds; none: the whole path
    int32_t after = -1;  ///< position of the box to be met first in the same list; -1: none
};

/// The QueryBox of `spec`. Throws std::invalid_argument saying what is wrong as a predicate that
/// follows the box's name ("box 2 tests no bodies: ..."): a degenerate rectangle or camera, no
/// bodies, a time window that ends before it starts, an `after` below -1.
QueryBox make_query_box(const ScreenBoxSpec& spec);

/// An orientation part as a goal file states it (degrees, directions of any length).
struct OrientationPartSpec {
    std::vector<uint32_t> bodies;
    Vec3 axis{0, 0, 1};    ///< in the body's own frame
    Vec3 target{0, 0, 1};  ///< in the world
    double within_deg = 0;
    double longer_than_s = 0;
    bool negative = false;
    std::optional<std::pair<double, double>> time_window;
    int32_t after = -1;
};

/// The goal part of `spec`, refused as make_query_box refuses boxes: no bodies, a tolerance
/// outside (0, 180) degrees, a zero axis or target, a negative duration, a reversed window.
QueryBox make_orientation_part(const OrientationPartSpec& spec);

/// Checks boxes as one goal: at least one, and every `after` names another box of the list with
/// no cycle (goal_order). Throws std::invalid_argument naming boxes from 1.
void check_goal(const std::vector<QueryBox>& boxes);

}  // namespace mwb
