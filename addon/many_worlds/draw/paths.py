"""The path overlay: the sampled paths of the chosen bodies in the 3D viewport, within a budget of
vertices (core.path_budget decides which paths, how thinned, and their colours).

Each object's paths have its own colour (core.palette; the panel's legend names them). Matching
worlds are drawn bright, the others faint and greyed (and, with Family of Selected World on, every
world outside that family). While a world is selected, the other paths are dimmed and the selected
world's paths are drawn last without depth test, so neither other paths nor the scene's geometry
hide them: a cyan band twice as wide with the objects' colours along its middle. A body is drawn
only in the worlds it exists in (bodies can be added to and removed from worlds).

Batches are built off the draw callback and reused between redraws: a timer compares their inputs
(the library's data and match state, LibraryView.version; the chosen and selected bodies; the
selected world; the budget) with those of the batches every POLL_S and, when they differ, rebuilds
them and redraws the 3D views; the draw callback only draws. The paths are thinned in screen space
for the view they are drawn in (core.screen_thinning): the draw callback notes each 3D view's
matrix and size, and once the view has stood still for a poll the batches are rebuilt for it, so
orbiting does not rebuild them on every frame. With more than one 3D view showing the paths they
are not thinned on screen (one view's thinning could be too coarse for another).
"""
import traceback

import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from .. import compat, scene_boxes
from ..core import palette, path_budget, screen_thinning
from ..core.session import SESSION
from .overlay import ViewportOverlay

SELECTED_COLOR = path_budget.SELECTED_COLOR
SELECTED_WIDTH = 2.0
# Seconds between checks of the batches' inputs (a change shows within this and one redraw).
POLL_S = 0.05


def selected_bodies(context, view):
    """Indices of the bodies of the selected objects."""
    selected = {ob.name for ob in context.view_layer.objects.selected}
    return tuple(i for i, name in enumerate(view.body_names) if name in selected)


def chosen_bodies(context, view):
    """Indices of the bodies whose paths are drawn: the selected objects' or every simulated one's,
    less those whose objects were deleted from the file since sampling."""
    bodies = selected_bodies(context, view) if context.scene.mwb.path_bodies == "SELECTED" else view.simulated_bodies()
    gone = scene_boxes.deleted_objects(view)
    return tuple(i for i in bodies if view.body_names[i] not in gone)


def tag_redraw_views():
    """Redraw the 3D views (their sidebars show the budget's line)."""
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else []):
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def open_view_regions():
    """Pointers of the main regions of every open 3D view."""
    wm = bpy.context.window_manager
    return {region.as_pointer()
            for window in (wm.windows if wm else []) for area in window.screen.areas if area.type == "VIEW_3D"
            for region in area.regions if region.type == "WINDOW"}


class PathOverlay(ViewportOverlay):
    draw_phase = "POST_VIEW"

    def __init__(self):
        super().__init__()
        self.vertex_budget = path_budget.VERTEX_BUDGET
        self.arrays = None       # core.path_budget.PathArrays of the batches, or None
        self.rebuilds = 0        # how often the arrays were built (tests count them)
        self._key = None
        self._batches = []       # (batch, width factor, drawn on top)
        self._shader = None
        self._views = {}          # region pointer -> ScreenView it was last drawn with
        self._seen_view = None    # the view the last poll saw (rebuilt for once it stands still)
        self._settled_view = None
        # One bound method for the timer: Blender finds a registered timer by the function object.
        self._timer = self._poll

    def add(self):
        super().add()
        if not bpy.app.timers.is_registered(self._timer):
            bpy.app.timers.register(self._timer, first_interval=0.0, persistent=True)

    def remove(self):
        if bpy.app.timers.is_registered(self._timer):
            bpy.app.timers.unregister(self._timer)
        super().remove()

    def forget(self):
        self.clear()

    def clear(self):
        self._key = None
        self.arrays = None
        self._batches = []

    def budget_text(self):
        """The panel's line when the budget leaves paths out, else ""."""
        return self.arrays.budget_text() if self.arrays is not None else ""

    # --- inputs and arrays ------------------------------------------------------------------------

    def inputs(self, context):
        """What the batches depend on (None: nothing to draw)."""
        view = SESSION.view
        if view is None or not context.scene.mwb.show_paths:
            return None
        settings = context.scene.mwb
        return (id(view), view.version, chosen_bodies(context, view), selected_bodies(context, view),
                settings.selected_world, settings.family_only, self.vertex_budget, self._screen_view())

    def _screen_view(self):
        """The ScreenView to thin paths for: the only 3D view drawing them, once it stood still for a
        poll (None with none or several)."""
        # A view closed since it last drew no longer counts.
        open_regions = open_view_regions()
        for pointer in [p for p in self._views if p not in open_regions]:
            del self._views[pointer]
        seen = next(iter(self._views.values())) if len(self._views) == 1 else None
        if seen == self._seen_view:
            self._settled_view = seen
        self._seen_view = seen
        return self._settled_view

    def update(self, context):
        """Rebuild the arrays and batches if their inputs changed; True if they were rebuilt."""
        key = self.inputs(context)
        if key == self._key:
            return False
        self._key = key
        if key is None:
            self.arrays, self._batches = None, []
            return True
        view = SESSION.view
        _, _, bodies, preferred, selected, family_only, budget, screen = key
        self.arrays = path_budget.build_path_arrays(self._choice(view, bodies, preferred, selected, family_only),
                                                    view.library.polylines, budget, screen)
        self.rebuilds += 1
        self._batches = [] if bpy.app.background else self._make_batches(self.arrays)
        return True

    @staticmethod
    def _choice(view, bodies, preferred, selected, family_only):
        matching = np.asarray(view.matching, dtype=bool)
        if family_only:
            family = view.family(selected)
            matching = matching & np.array([w in family for w in view.world_indices], dtype=bool)
        colours = palette.body_colours(view.body_names, view.simulated_bodies())
        return path_budget.PathChoice(list(view.world_indices), matching, selected, bodies, preferred, colours)

    # --- batches ----------------------------------------------------------------------------------

    def _make_batches(self, arrays):
        if self._shader is None:
            self._shader = compat.builtin_shader("POLYLINE_FLAT_COLOR")
        batches = []
        if len(arrays.others):
            batches.append((self._batch(arrays.others, arrays.other_colours), 1.0, False))
        if len(arrays.selected):
            band = path_budget.selected_band_colours(len(arrays.selected))
            batches.append((self._batch(arrays.selected, band), SELECTED_WIDTH, True))
            batches.append((self._batch(arrays.selected, arrays.selected_colours), 1.0, True))
        return batches

    def _batch(self, positions, colours):
        return batch_for_shader(self._shader, "LINES", {"pos": positions, "color": np.ascontiguousarray(colours)})

    def _poll(self):
        """Timer: rebuild the batches if their inputs changed, then redraw the 3D views."""
        try:
            if self.update(bpy.context):
                tag_redraw_views()
        except Exception:
            # Keep polling: one failed build must not stop the paths from updating later.
            traceback.print_exc()
        return POLL_S

    # --- drawing ----------------------------------------------------------------------------------

    def draw(self):
        context = bpy.context
        if not self._batches or SESSION.view is None or not context.scene.mwb.show_paths:
            return
        width = context.scene.mwb.path_width
        region = context.region
        matrix = context.region_data.perspective_matrix
        self._views[region.as_pointer()] = screen_thinning.ScreenView(
            tuple(tuple(row) for row in matrix), region.width, region.height)
        blend, depth, line_width = gpu.state.blend_get(), gpu.state.depth_test_get(), gpu.state.line_width_get()
        gpu.state.blend_set("ALPHA")
        try:
            self._shader.bind()
            self._shader.uniform_float("viewportSize", (region.width, region.height))
            for batch, factor, on_top in self._batches:
                gpu.state.depth_test_set("NONE" if on_top else "LESS_EQUAL")
                self._shader.uniform_float("lineWidth", width * factor)
                batch.draw(self._shader)
        finally:
            gpu.state.blend_set(blend)
            gpu.state.depth_test_set(depth)
            gpu.state.line_width_set(line_width)


OVERLAY = PathOverlay()
