"""The path overlay: every sampled path of the chosen bodies in the 3D viewport.

Each object's paths have its own colour (core.palette; the panel's legend names them). Matching
worlds are drawn bright, the others faint and greyed (and, with Family of Selected World on, every
world outside that family). While a world is selected, the other paths are dimmed and the selected
world's paths are drawn last without depth test, so neither other paths nor the scene's geometry
hide them: a cyan band twice as wide with the objects' colours along its middle. A body is drawn
only in the worlds it exists in (bodies can be added to and removed from worlds). Batches are
cached and rebuilt only when the library's data or match state (LibraryView.version), the chosen
bodies or the selected world change; per-world line segments are cached too, so a new world
costs only its own arrays.
"""
import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from .. import compat
from ..core import arrays, palette
from ..core.session import SESSION
from .overlay import ViewportOverlay

SELECTED_COLOR = (0.1, 0.85, 1.0, 1.0)
# While a world is selected, the other paths' alpha is scaled by this, so the selected one stands out.
DIMMED_ALPHA = 0.35
SELECTED_WIDTH = 2.0


def dimmed(colour):
    return colour[:3] + (colour[3] * DIMMED_ALPHA,)


def chosen_bodies(context, view):
    if context.scene.mwb.path_bodies == "SELECTED":
        selected = {ob.name for ob in context.selected_objects}
        return tuple(i for i, name in enumerate(view.body_names) if name in selected)
    return tuple(view.simulated_bodies())


class PathOverlay(ViewportOverlay):
    draw_phase = "POST_VIEW"

    def __init__(self):
        super().__init__()
        self._key = None
        self._batches = []       # (batch, colour, width factor, drawn on top)
        self._segments = {}      # (world, bodies) -> float32 (n, 3)
        self._shader = None

    def forget(self):
        self.clear()

    def clear(self):
        self._key = None
        self._batches = []
        self._segments = {}

    # --- batches ------------------------------------------------------------------------------

    def world_segments(self, view, world, bodies):
        """Line-list vertices of the paths of `bodies` that exist in `world` (cached)."""
        key = (world, bodies)
        if key not in self._segments:
            self._segments[key] = arrays.polyline_segments(view.library.polyline(world),
                                                           view.present_bodies(world, bodies))
        return self._segments[key]

    def _batch(self, parts):
        parts = [p for p in parts if len(p)]
        if not parts:
            return None
        return batch_for_shader(self._shader, "LINES", {"pos": np.concatenate(parts)})

    def _colour_groups(self, view, bodies):
        """[(colour, bodies)]: the chosen bodies grouped by their object's colour."""
        colours = palette.body_colours(view.body_names, view.simulated_bodies())
        groups = {}
        for b in bodies:
            groups.setdefault(colours[b], []).append(b)
        return [(colour, tuple(group)) for colour, group in groups.items()]

    def _rebuild(self, view, bodies, selected, family_only):
        if self._shader is None:
            self._shader = compat.builtin_shader("POLYLINE_UNIFORM_COLOR")
        family = view.family(selected) if family_only else None
        has_selected = selected in view.world_indices
        groups = self._colour_groups(view, bodies)
        self._batches = []
        # Rejected worlds first, so matching ones draw over them.
        for is_match, shade in ((False, palette.rejected), (True, palette.matching)):
            for colour, group in groups:
                parts = [self.world_segments(view, world, group)
                         for world, match in zip(view.world_indices, view.matching)
                         if world != selected and bool(match and (family is None or world in family)) == is_match]
                batch = self._batch(parts)
                if batch is not None:
                    colour = shade(colour)
                    self._batches.append((batch, dimmed(colour) if has_selected else colour, 1.0, False))
        if has_selected:
            band = self._batch([self.world_segments(view, selected, bodies)])
            if band is not None:
                self._batches.append((band, SELECTED_COLOR, SELECTED_WIDTH, True))
            for colour, group in groups:
                batch = self._batch([self.world_segments(view, selected, group)])
                if batch is not None:
                    self._batches.append((batch, colour[:3] + (1.0,), 1.0, True))

    def batches_for(self, context):
        """The batches to draw now (rebuilt if their inputs changed); [] when there is nothing."""
        view = SESSION.view
        if view is None or not context.scene.mwb.show_paths:
            return []
        bodies = chosen_bodies(context, view)
        selected = context.scene.mwb.selected_world
        family_only = context.scene.mwb.family_only
        key = (id(view), view.version, bodies, selected, family_only)
        if key != self._key:
            if self._key is None or self._key[0] != id(view):
                self._segments = {}
            self._rebuild(view, bodies, selected, family_only)
            self._key = key
        return self._batches

    # --- drawing --------------------------------------------------------------------------------

    def draw(self):
        context = bpy.context
        batches = self.batches_for(context)
        if not batches:
            return
        width = context.scene.mwb.path_width
        region = context.region
        blend, depth, line_width = gpu.state.blend_get(), gpu.state.depth_test_get(), gpu.state.line_width_get()
        gpu.state.blend_set("ALPHA")
        try:
            self._shader.bind()
            self._shader.uniform_float("viewportSize", (region.width, region.height))
            for batch, colour, factor, on_top in batches:
                gpu.state.depth_test_set("NONE" if on_top else "LESS_EQUAL")
                self._shader.uniform_float("lineWidth", width * factor)
                self._shader.uniform_float("color", colour)
                batch.draw(self._shader)
        finally:
            gpu.state.blend_set(blend)
            gpu.state.depth_test_set(depth)
            gpu.state.line_width_set(line_width)


OVERLAY = PathOverlay()
