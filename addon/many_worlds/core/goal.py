"""The goal of a seek as the file `mwb-engine seek --goal` reads, without bpy.

A goal is a list of parts that a world must all meet: query boxes (BoxSpec) and pose parts
(PoseSpec); a part may have to be met after another one (its `after`, a position in the list).
The file is JSON:

    {"boxes": [{"view": [16], "projection": [16], "viewport": [w, h], "rect": [x0, y0, x1, y1],
                "bodies": [i, ...], "negative": false, "swept": false,
                "time_window": [t0_s, t1_s] or null, "after": null or a position}],
     "orientations": [{"bodies": [i, ...], "axis": [x, y, z], "target": [x, y, z],
                       "within_deg": d, "negative": false, "longer_than_s": s,
                       "time_window": [t0_s, t1_s] or null, "after": null or a position}]}

view and projection are row-major (world to camera, camera to clip, OpenGL); rect is in pixels
from the viewport's bottom-left; bodies are the library scene's body indices. Positions count
the boxes first, then the orientation parts. The engine also takes "objects" (names) in place of
"bodies"; what is written here always names bodies.
"""
import json

import numpy as np

from .. import _native
from .library_query import PoseSpec, native_parts


def _checked(specs):
    """The specs, once the module (query/ScreenBox.h) accepts each part and the goal they make."""
    specs = list(specs)
    _native.check_goal(native_parts(specs))
    return specs


def file_order(specs):
    """The positions of `specs` in the file: boxes first, then pose parts, each in list order."""
    boxes = [k for k, spec in enumerate(specs) if not isinstance(spec, PoseSpec)]
    poses = [k for k, spec in enumerate(specs) if isinstance(spec, PoseSpec)]
    return boxes + poses


def goal_document(specs):
    """The goal file's content (a dict) for the BoxSpecs and PoseSpecs `specs`.

    Raises ValueError, as the engine would refuse the goal: no parts, a part the module refuses
    (no bodies, a degenerate rectangle, a tolerance outside 0 to 180 degrees, a window that ends
    before it starts), an `after` that is the part itself or outside the list, or an ordering cycle.
    """
    specs = _checked(specs)
    order = file_order(specs)
    position = {k: n for n, k in enumerate(order)}

    def window_and_after(spec):
        return {"time_window": [float(t) for t in spec.time_window] if spec.time_window is not None else None,
                "after": position[int(spec.after)] if spec.after >= 0 else None}

    def box(spec):
        return {"view": np.asarray(spec.view, dtype=np.float64).reshape(16).tolist(),
                "projection": np.asarray(spec.projection, dtype=np.float64).reshape(16).tolist(),
                "viewport": [float(spec.size[0]), float(spec.size[1])],
                "rect": [float(v) for v in spec.rect],
                "bodies": [int(b) for b in spec.bodies],
                "negative": bool(spec.negative), "swept": bool(spec.swept), **window_and_after(spec)}

    def pose(spec):
        return {"bodies": [int(b) for b in spec.bodies], "axis": [float(v) for v in spec.axis],
                "target": [float(v) for v in spec.target], "within_deg": float(spec.within_deg),
                "negative": bool(spec.negative), "longer_than_s": float(spec.longer_than_s),
                **window_and_after(spec)}

    document = {"boxes": [box(specs[k]) for k in order if not isinstance(specs[k], PoseSpec)]}
    poses = [pose(specs[k]) for k in order if isinstance(specs[k], PoseSpec)]
    if poses:
        document["orientations"] = poses
    return document


def write_goal(path, specs):
    """Write the goal file for `specs` at `path` (see goal_document). Returns `path`."""
    document = goal_document(specs)
    with open(path, "w") as f:
        json.dump(document, f, indent=1)
        f.write("\n")
    return path
