#pragma once
// A goal file: the parts (boxes and poses) a search must meet, as the add-on and command line
// write them.
//
//   {"boxes": [{"view": [16 numbers, row-major world to camera],
//               "projection": [16 numbers, row-major camera to clip, OpenGL],
//               "viewport": [width, height], "rect": [x0, y0, x1, y1] (pixels from the bottom-left),
//               "bodies": [scene body indices] or "objects": ["Name", ...],
//               "negative": false, "swept": false, "time_window": [t0, t1] or null,
//               "after": null or the position of the part this one must be met after}],
//    "orientations": [{"objects": [...] or "bodies": [...], "within_deg": 20,
//               "axis": [0, 0, 1] (the body's own, default up), "target": [0, 0, 1] (the world's),
//               "negative": false, "longer_than_s": 0, "time_window": [t0, t1] or null,
//               "after": null or the position of a part}]}   (optional)
// A positive orientation part holds when every named body's axis stays within within_deg of the
// target over the window; a negative one when none stays within for longer than longer_than_s.
// Positions count the boxes first, then the orientation parts: part k of "orientations" is goal
// part len(boxes) + k, and a part may follow a box or another orientation part.
#include <stdexcept>
#include <string>
#include <vector>

#include "query/PathIndex.h"
#include "scene/Scene.h"

namespace mwb {

/// A goal that cannot be searched for (no parts, an object the library lacks, an ordering
/// cycle, a malformed file); the message is one line.
struct GoalError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The goal's boxes, with body names resolved against `scene` (every body standing for a named
/// object). Throws GoalError.
std::vector<QueryBox> goal_from_json(const std::string& text, const Scene& scene);

}  // namespace mwb
