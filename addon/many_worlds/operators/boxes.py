"""Query boxes: drawing one in the viewport (modal), adding one from numbers, editing the list,
and choosing the bodies a ranking is computed over.

Box tool: Ctrl+Alt+left-drag in the 3D Viewport (Object Mode) draws a positive box; hold Shift
(Ctrl+Alt+Shift+left-drag, or press Shift while dragging) for a negative box. From the sidebar
button or the toolbar tool, press and drag with the left mouse. Esc or right-click cancels.
"""
import bpy
from bpy.props import BoolProperty, FloatVectorProperty, IntProperty, IntVectorProperty, StringProperty
from mathutils import Matrix

from .. import scene_boxes
from ..core.library_query import normalized_rect, too_small_text
from ..core.session import SESSION
from ..draw import boxes as box_overlay

# Navigation stays usable while waiting for the press that starts a box.
_NAVIGATION = {"MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "WHEELINMOUSE", "WHEELOUTMOUSE",
               "TRACKPADPAN", "TRACKPADZOOM", "NDOF_MOTION"}


def viewport_at(window, x, y):
    """(area, region) of the 3D viewport region under window coordinates (x, y), or (None, None)."""
    for area in window.screen.areas:
        if area.type != "VIEW_3D":
            continue
        for region in area.regions:
            if (region.type == "WINDOW" and region.x <= x < region.x + region.width
                    and region.y <= y < region.y + region.height):
                return area, region
    return None, None


def camera_of(operator, context):
    """(view, projection, region size) from the operator's properties, each missing one from the
    current 3D view; None (reported) when neither is there."""
    view, projection = list(operator.view_matrix), list(operator.projection_matrix)
    size = tuple(operator.region_size)
    region, region_3d = context.region, context.region_data
    if not any(view) or not any(projection) or 0 in size:
        if region_3d is None:
            operator.report({"ERROR"}, "Give the view, projection and region size, or run in a 3D viewport")
            return None
        view = view if any(view) else [v for row in region_3d.view_matrix for v in row]
        projection = projection if any(projection) else [v for row in region_3d.window_matrix for v in row]
        size = size if 0 not in size else (region.width, region.height)
    return view, projection, size


class BoxDrag:
    """The modal part of drawing a box in a 3D viewport, shared by the query box and refine tools.

    A subclass sets `_hint` (status bar text while waiting for the press) and implements
    `_prepare(context)` (False cancels; it reports why), `_dragged(context, event)` (header text
    while dragging) and `_released(context, event, rect)` (the operator's result).
    """

    _hint = ""

    # --- state ---------------------------------------------------------------------------------

    def _start(self, context, x, y):
        area, region = viewport_at(context.window, x, y)
        if region is None or region.data is None:
            return False
        self._area, self._region = area, region
        self._start_px = (x - region.x, y - region.y)
        self._end_px = self._start_px
        self._dragging = True
        return True

    def _rect(self):
        return normalized_rect(*self._start_px, *self._end_px)

    def _update(self, context, event):
        region = self._region
        self._end_px = (event.mouse_x - region.x, event.mouse_y - region.y)
        self._area.header_text_set(self._dragged(context, event))
        self._area.tag_redraw()

    def _end(self, context):
        box_overlay.OVERLAY.dragging = None
        if self._area is not None:
            self._area.header_text_set(None)
            self._area.tag_redraw()

    # --- operator -------------------------------------------------------------------------------

    def invoke(self, context, event):
        self._area = self._region = None
        self._dragging = False
        if not self._prepare(context):
            return {"CANCELLED"}
        if event.type == "LEFTMOUSE" and event.value == "CLICK_DRAG":
            # Started by a click-drag keymap item: the box begins where the button went down.
            # (A button in the sidebar also invokes with a left-mouse event, but not a drag.)
            self._start(context, event.mouse_prev_press_x, event.mouse_prev_press_y)
        context.window_manager.modal_handler_add(self)
        if self._dragging:
            self._update(context, event)
        else:
            context.workspace.status_text_set(self._hint)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            return self._cancel(context)
        if not self._dragging:
            if event.type == "LEFTMOUSE" and event.value == "PRESS":
                if self._start(context, event.mouse_x, event.mouse_y):
                    context.workspace.status_text_set(None)
                    self._update(context, event)
                return {"RUNNING_MODAL"}
            return {"PASS_THROUGH"} if event.type in _NAVIGATION else {"RUNNING_MODAL"}
        if event.type == "LEFTMOUSE" and event.value == "RELEASE":
            self._end_px = (event.mouse_x - self._region.x, event.mouse_y - self._region.y)
            problem = too_small_text(self._rect())
            if problem:
                # A click, or a drag along a line: said, never dropped in silence.
                self.report({"WARNING"}, problem)
                SESSION.box_note = problem
                return self._cancel(context)
            SESSION.box_note = ""
            self._end(context)
            x0, y0, x1, y1 = self._rect()
            return self._released(context, event, (x0, y0, x1, y1))
        if event.type in {"MOUSEMOVE", "LEFT_SHIFT", "RIGHT_SHIFT", "INBETWEEN_MOUSEMOVE"}:
            self._update(context, event)
        return {"RUNNING_MODAL"}

    def _cancel(self, context):
        self._end(context)
        context.workspace.status_text_set(None)
        scene_boxes.refresh(context.scene)
        return {"CANCELLED"}


class MWB_OT_draw_box(BoxDrag, bpy.types.Operator):
    """Drag a query box in the 3D viewport: keep worlds whose paths enter it (Shift: stay out of it)"""
    bl_idname = "mwb.draw_box"
    bl_label = "Draw Query Box"
    bl_options = {"REGISTER", "UNDO"}

    negative: BoolProperty(name="Negative", default=False,
                           description="Draw a negative box (Shift while dragging does the same)")

    _hint = "Many Worlds: drag a box in the 3D viewport (Shift: negative; Esc / right-click: cancel)"

    @classmethod
    def poll(cls, context):
        return context.window is not None and hasattr(context.scene, "mwb")

    def _is_negative(self, event):
        return self.negative or event.shift

    def _prepare(self, context):
        self._bodies, left_out = scene_boxes.body_choice(context)
        if not self._bodies:
            self.report({"WARNING"}, "No simulated rigid bodies to query")
            return False
        if left_out:
            self.report({"WARNING"}, scene_boxes.left_out_text(left_out))
        return True

    def _dragged(self, context, event):
        region = self._region
        negative = self._is_negative(event)
        box_overlay.OVERLAY.dragging = (region.as_pointer(), self._rect(), negative)
        spec = None
        if SESSION.view is not None:
            spec = scene_boxes.drag_spec(SESSION.view, region.data.view_matrix, region.data.window_matrix,
                                     (region.width, region.height), self._rect(), negative, self._bodies)
        # The match count follows the box while it is dragged: one query per mouse move.
        scene_boxes.refresh(context.scene, extra=spec)
        kind = "negative" if negative else "positive"
        return (f"{scene_boxes.match_text() or 'No library open'} | {kind} box | "
                "Shift: negative | Esc / right-click: cancel")

    def _released(self, context, event, rect):
        region = self._region
        scene_boxes.store_box(context.scene, region.data.view_matrix, region.data.window_matrix,
                          (region.width, region.height), rect, self._is_negative(event), self._bodies)
        scene_boxes.refresh(context.scene)
        self.report({"INFO"}, scene_boxes.match_text() or "Box stored; open a library to query it")
        return {"FINISHED"}


class MWB_OT_add_box(bpy.types.Operator):
    """Add a query box from a rectangle and the view it was drawn in (scripts, tests, precise boxes)"""
    bl_idname = "mwb.add_box"
    bl_label = "Add Query Box"
    bl_options = {"REGISTER", "UNDO"}

    rect: FloatVectorProperty(name="Rectangle", size=4, description="x0, y0, x1, y1, region pixels")
    view_matrix: FloatVectorProperty(name="View Matrix", size=16,
                                     description="World to camera, row-major; all zero: the current 3D view's")
    projection_matrix: FloatVectorProperty(name="Projection Matrix", size=16,
                                           description="Camera to clip, row-major; all zero: the current 3D view's")
    region_size: IntVectorProperty(name="Region Size", size=2, description="Width, height; 0: the current region's")
    negative: BoolProperty(name="Negative", default=False)
    bodies: StringProperty(name="Bodies", description="Comma-separated object names; empty: the selected ones. "
                                                       "Only simulated bodies are kept")

    def execute(self, context):
        camera = camera_of(self, context)
        if camera is None:
            return {"CANCELLED"}
        view, projection, size = camera
        asked = [n.strip() for n in self.bodies.split(",") if n.strip()]
        names, left_out = scene_boxes.body_choice(context, asked or None)
        if left_out:
            self.report({"WARNING"}, scene_boxes.left_out_text(left_out))
        problem = too_small_text(self.rect)
        if problem:
            self.report({"ERROR"}, problem)
            return {"CANCELLED"}
        x0, y0, x1, y1 = normalized_rect(*self.rect)
        scene_boxes.store_box(context.scene, [view[i:i + 4] for i in range(0, 16, 4)],
                          [projection[i:i + 4] for i in range(0, 16, 4)], size, (x0, y0, x1, y1),
                          self.negative, names)
        scene_boxes.refresh(context.scene)
        return {"FINISHED"}


def part_at(context, index):
    """(index, the box or pose part at `index` of the scene's list, or None); -1: the active one."""
    boxes = context.scene.mwb.boxes
    index = context.scene.mwb.box_index if index < 0 else index
    return (index, boxes[index]) if 0 <= index < len(boxes) else (index, None)


class MWB_OT_remove_box(bpy.types.Operator):
    """Delete a query box or pose part"""
    bl_idname = "mwb.remove_box"
    bl_label = "Remove Box"
    bl_options = {"REGISTER", "UNDO"}

    index: IntProperty(name="Index", default=-1, description="Box or pose part to remove; -1: the active one")

    def execute(self, context):
        index, box = part_at(context, self.index)
        if box is None:
            return {"CANCELLED"}
        settings = context.scene.mwb
        scene_boxes.remove_box(context.scene, index)
        settings.box_index = min(settings.box_index, len(settings.boxes) - 1)
        scene_boxes.refresh(context.scene)
        return {"FINISHED"}


class MWB_OT_clear_boxes(bpy.types.Operator):
    """Delete every query box and pose part: all worlds match again"""
    bl_idname = "mwb.clear_boxes"
    bl_label = "Clear Boxes and Poses"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        context.scene.mwb.boxes.clear()
        context.scene.mwb.box_index = -1
        scene_boxes.refresh(context.scene)
        return {"FINISHED"}


class MWB_OT_box_use_selected(bpy.types.Operator):
    """Make the box or pose test the selected objects the simulation moves (passive and animated ones are left out)"""
    bl_idname = "mwb.box_use_selected"
    bl_label = "Use Selected"
    bl_options = {"REGISTER", "UNDO"}

    index: IntProperty(name="Index", default=-1, description="Box or pose part to change; -1: the active one")

    def execute(self, context):
        _, box = part_at(context, self.index)
        if box is None:
            return {"CANCELLED"}
        names, left_out = scene_boxes.body_choice(context)
        if left_out:
            self.report({"WARNING"}, scene_boxes.left_out_text(left_out))
        box.bodies.clear()
        for name in names:
            box.bodies.add().name = name
        scene_boxes.refresh(context.scene)
        return {"FINISHED"}


class MWB_OT_view_box(bpy.types.Operator):
    """Look through the view the box was drawn in, so it is drawn again"""
    bl_idname = "mwb.view_box"
    bl_label = "View Box"

    index: IntProperty(name="Index", default=-1, description="Box to view; -1: the active one")

    @classmethod
    def poll(cls, context):
        return getattr(context.space_data, "type", "") == "VIEW_3D"

    def execute(self, context):
        _, box = part_at(context, self.index)
        if box is None or box.kind == "POSE":
            return {"CANCELLED"}
        region_3d = context.space_data.region_3d
        stored = list(box.view_matrix)
        # The projection's last row says perspective (0, 0, -1, 0) or orthographic (0, 0, 0, 1).
        region_3d.view_perspective = "ORTHO" if box.projection_matrix[15] == 1.0 else "PERSP"
        region_3d.view_matrix = Matrix([stored[i:i + 4] for i in range(0, 16, 4)])
        return {"FINISHED"}


class MWB_OT_rank_use_selected(bpy.types.Operator):
    """Rank by the metric of the selected objects (stored; selecting other objects later keeps them)"""
    bl_idname = "mwb.rank_use_selected"
    bl_label = "Use Selected"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        settings = context.scene.mwb
        names, left_out = scene_boxes.body_choice(context)
        if left_out:
            self.report({"WARNING"}, scene_boxes.left_out_text(left_out))
        settings.rank_body_names.clear()
        for name in names:
            settings.rank_body_names.add().name = name
        settings.rank_bodies = "LISTED"
        return {"FINISHED"}


classes = (MWB_OT_draw_box, MWB_OT_add_box, MWB_OT_remove_box, MWB_OT_clear_boxes, MWB_OT_box_use_selected,
           MWB_OT_view_box, MWB_OT_rank_use_selected)
