"""The box overlay: query boxes in region pixels (POST_PIXEL), and the box being dragged.

A stored box is a frustum fixed by the view it was drawn in. It is drawn only in a viewport whose
view matrix, projection and size equal the stored ones (within float noise): from any other view
the frustum is no longer a rectangle, and a rectangle drawn there would lie about what the box
keeps. The Boxes list marks boxes drawn through another view; "View Box" restores that view.
"""
import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from .. import compat
from .overlay import ViewportOverlay

POSITIVE_COLOR = (0.1, 0.9, 0.25, 1.0)
NEGATIVE_COLOR = (0.95, 0.12, 0.1, 1.0)
FILL_ALPHA = 0.12
DISABLED_ALPHA = 0.35
OUTLINE_WIDTH = 2.0
MATRIX_TOLERANCE = 1e-4


def view_matches(box, region, region_3d):
    """True when region shows the view the box was drawn in."""
    if tuple(box.region_size) != (region.width, region.height):
        return False
    stored_view = np.array(box.view_matrix).reshape(4, 4)
    stored_projection = np.array(box.projection_matrix).reshape(4, 4)
    return (np.allclose(stored_view, np.array(region_3d.view_matrix), atol=MATRIX_TOLERANCE)
            and np.allclose(stored_projection, np.array(region_3d.window_matrix), atol=MATRIX_TOLERANCE))


def _outline(rect):
    x0, y0, x1, y1 = rect
    a, b, c, d = (x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)
    return [a, b, b, c, c, d, d, a]


def _fill(rect):
    x0, y0, x1, y1 = rect
    return [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y0, 0), (x1, y1, 0), (x0, y1, 0)]


class BoxOverlay(ViewportOverlay):
    def __init__(self):
        super().__init__()
        self._line_shader = None
        self._fill_shader = None
        # The box being dragged: (region pointer, (x0, y0, x1, y1), negative) or None.
        self.dragging = None

    def forget(self):
        self.dragging = None

    def rectangles(self, context):
        """(rect, colour) of every box to draw in context.region, the dragged one last."""
        region, region_3d = context.region, context.region_data
        out = []
        mwb = getattr(context.scene, "mwb", None)
        if mwb is not None and region_3d is not None:
            for box in mwb.boxes:
                # Pose parts are drawn on their objects (draw/poses.py).
                if box.kind != "POSE" and view_matches(box, region, region_3d):
                    colour = NEGATIVE_COLOR if box.negative else POSITIVE_COLOR
                    if not box.enabled:
                        colour = (*colour[:3], DISABLED_ALPHA)
                    out.append((tuple(box.rect), colour))
        if self.dragging is not None and self.dragging[0] == region.as_pointer():
            out.append((self.dragging[1], NEGATIVE_COLOR if self.dragging[2] else POSITIVE_COLOR))
        return out

    def draw(self):
        context = bpy.context
        rectangles = self.rectangles(context)
        if not rectangles:
            return
        if self._line_shader is None:
            self._line_shader = compat.builtin_shader("POLYLINE_UNIFORM_COLOR")
            self._fill_shader = compat.builtin_shader("UNIFORM_COLOR")
        region = context.region
        blend = gpu.state.blend_get()
        gpu.state.blend_set("ALPHA")
        try:
            for rect, colour in rectangles:
                fill = batch_for_shader(self._fill_shader, "TRIS", {"pos": _fill(rect)})
                self._fill_shader.bind()
                self._fill_shader.uniform_float("color", (*colour[:3], FILL_ALPHA * colour[3]))
                fill.draw(self._fill_shader)
                outline = batch_for_shader(self._line_shader, "LINES", {"pos": _outline(rect)})
                self._line_shader.bind()
                self._line_shader.uniform_float("viewportSize", (region.width, region.height))
                self._line_shader.uniform_float("lineWidth", OUTLINE_WIDTH)
                self._line_shader.uniform_float("color", colour)
                outline.draw(self._line_shader)
        finally:
            gpu.state.blend_set(blend)


OVERLAY = BoxOverlay()
