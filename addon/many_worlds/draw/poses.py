"""Pose parts drawn on their objects in the 3D views (world space, POST_VIEW), as the objects stand
at the frame shown (while a world is previewed, that world's pose).

From each object's origin: the direction the part wants, with the cone of its tolerance around it
(a circle and a few lines from the origin), green for a positive part and red for a negative one
like the boxes; and the object's own axis that the part tests, white while it is within the
tolerance and yellow while it is not. Drawn on top of the scene, so a line that starts inside the
object still shows.
"""
import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from .. import compat, pose_parts
from ..core import pose_target
from .boxes import DISABLED_ALPHA, NEGATIVE_COLOR, POSITIVE_COLOR
from .overlay import ViewportOverlay

WITHIN_COLOR = (1.0, 1.0, 1.0, 1.0)
OUTSIDE_COLOR = (1.0, 0.85, 0.1, 1.0)
LINE_WIDTH = 2.0
# Lines from the origin, as long as this times the object's largest dimension: well outside it.
LENGTH_PER_SIZE = 2.0


def _dimmed(colour, enabled):
    return colour if enabled else (*colour[:3], DISABLED_ALPHA)


def pose_lines(context):
    """{colour: [(n, 3) line segment points, ...]} of every pose part on its visible objects."""
    out = {}
    mwb = getattr(context.scene, "mwb", None)
    for part in (mwb.boxes if mwb is not None else []):
        directions = pose_parts.directions(part) if part.kind == "POSE" else None
        if directions is None:
            continue
        axis, target = directions
        cone_colour = _dimmed(NEGATIVE_COLOR if part.negative else POSITIVE_COLOR, part.enabled)
        for item in part.bodies:
            ob = context.scene.objects.get(item.name)
            if ob is None or not ob.visible_get():
                continue
            rotation = pose_parts.object_rotation(ob)
            origin = np.array(ob.matrix_world.translation)
            length = LENGTH_PER_SIZE * (max(ob.dimensions) or 1.0)
            out.setdefault(cone_colour, []).append(
                pose_target.cone_segments(origin, target, part.within_deg, length))
            within = pose_target.angle_deg(rotation, axis, target) <= part.within_deg
            turned = rotation @ np.asarray(axis, dtype=np.float64)
            tip = origin + turned / np.linalg.norm(turned) * length
            out.setdefault(_dimmed(WITHIN_COLOR if within else OUTSIDE_COLOR, part.enabled), []).append(
                np.array([origin, tip]))
    return out


class PoseOverlay(ViewportOverlay):
    draw_phase = "POST_VIEW"

    def __init__(self):
        super().__init__()
        self._shader = None

    def draw(self):
        context = bpy.context
        lines = pose_lines(context)
        if not lines:
            return
        if self._shader is None:
            self._shader = compat.builtin_shader("POLYLINE_UNIFORM_COLOR")
        shader, region = self._shader, context.region
        blend, depth = gpu.state.blend_get(), gpu.state.depth_test_get()
        gpu.state.blend_set("ALPHA")
        gpu.state.depth_test_set("NONE")
        try:
            for colour, segments in lines.items():
                batch = batch_for_shader(shader, "LINES", {"pos": np.concatenate(segments).astype(np.float32)})
                shader.bind()
                shader.uniform_float("viewportSize", (region.width, region.height))
                shader.uniform_float("lineWidth", LINE_WIDTH)
                shader.uniform_float("color", colour)
                batch.draw(shader)
        finally:
            gpu.state.blend_set(blend)
            gpu.state.depth_test_set(depth)


OVERLAY = PoseOverlay()
