"""The goal of a seek as the file `mwb-engine seek --goal` reads, without bpy.

A goal is a list of query boxes (BoxSpec) that a world must all meet; a box may have to be met
after another one (BoxSpec.after, its position in the list). The file is JSON:

    {"boxes": [{"view": [16], "projection": [16], "viewport": [w, h], "rect": [x0, y0, x1, y1],
                "bodies": [i, ...], "negative": false, "swept": false,
                "time_window": [t0_s, t1_s] or null, "after": null or a position in "boxes"}]}

view and projection are row-major (world to camera, camera to clip, OpenGL); rect is in pixels
from the viewport's bottom-left; bodies are the library scene's body indices. The engine also
takes "objects" (names) in place of "bodies"; what is written here always names bodies.
"""
import json

import numpy as np

from .. import _native
from .library_query import BoxSpec, native_box


def _checked(specs):
    """The specs, once the module (query/ScreenBox.h) accepts each box and the goal they make."""
    specs = list(specs)
    boxes = []
    for k, spec in enumerate(specs):
        try:
            boxes.append(native_box(spec))
        except ValueError as error:
            raise ValueError(f"box {k + 1} {error}") from None
    _native.check_goal(boxes)
    return specs


def goal_document(specs):
    """The goal file's content (a dict) for the BoxSpecs `specs`, in their order.

    Raises ValueError, as the engine would refuse the goal: no boxes, a box the module refuses (no
    bodies, a degenerate rectangle, a window that ends before it starts), an `after` that is the
    box itself or outside the list, or an ordering cycle.
    """
    def box(spec):
        return {"view": np.asarray(spec.view, dtype=np.float64).reshape(16).tolist(),
                "projection": np.asarray(spec.projection, dtype=np.float64).reshape(16).tolist(),
                "viewport": [float(spec.size[0]), float(spec.size[1])],
                "rect": [float(v) for v in spec.rect],
                "bodies": [int(b) for b in spec.bodies],
                "negative": bool(spec.negative), "swept": bool(spec.swept),
                "time_window": [float(t) for t in spec.time_window] if spec.time_window is not None else None,
                "after": int(spec.after) if spec.after >= 0 else None}
    return {"boxes": [box(spec) for spec in _checked(specs)]}


def write_goal(path, specs):
    """Write the goal file for `specs` at `path` (see goal_document). Returns `path`."""
    document = goal_document(specs)
    with open(path, "w") as f:
        json.dump(document, f, indent=1)
        f.write("\n")
    return path


def goal_specs(document):
    """The BoxSpecs of a goal file's content written by goal_document (bodies, not objects)."""
    specs = []
    for k, box in enumerate(document.get("boxes", [])):
        if "bodies" not in box:
            raise ValueError(f"box {k + 1} names objects, not bodies: the library's scene resolves them")
        window = box.get("time_window")
        after = box.get("after")
        specs.append(BoxSpec(view=np.array(box["view"], dtype=np.float64).reshape(4, 4),
                             projection=np.array(box["projection"], dtype=np.float64).reshape(4, 4),
                             size=(box["viewport"][0], box["viewport"][1]), rect=tuple(box["rect"]),
                             negative=bool(box.get("negative", False)), bodies=tuple(box["bodies"]),
                             time_window=tuple(window) if window is not None else None,
                             swept=bool(box.get("swept", False)), after=-1 if after is None else int(after)))
    return _checked(specs)


def read_goal(path):
    """The BoxSpecs of the goal file at `path`."""
    with open(path) as f:
        return goal_specs(json.load(f))
