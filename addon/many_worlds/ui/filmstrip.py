"""Thumbnails in the ranking: each row's world at its last frame, and under the list a filmstrip
of the selected world (its row expanded): FRAMES moments from start to rest, with their times.
The filmstrip's button opens it large, in a popup as wide as POPUP_FRAME_PIXELS per frame."""
import bpy

from .. import posing
from ..core.session import SESSION
from ..thumbnails import THUMBNAILS
from .fit import wrapped_labels

FRAMES = 6
SIDEBAR_COLUMNS = 3  # the sidebar is narrow: the filmstrip folds into rows of three
SCALE = 3.0          # filmstrip pictures in the sidebar, in rows of the UI
POPUP_SCALE = 7.0    # and in the popup
POPUP_FRAME_PIXELS = 160


def row_icon(context, world):
    """Keyword arguments of a label's icon for a ranking row: the world's thumbnail, or an
    hourglass while it is being made; no icon without a scene camera."""
    if context.scene.camera is None:
        return {}
    icon = THUMBNAILS.icon(context.scene, world)
    return {"icon_value": icon} if icon else {"icon": "TIME"}


def draw_frames(layout, context, world, scale, columns=FRAMES):
    """The world's filmstrip: FRAMES pictures, `columns` to a row, each with its time."""
    view = SESSION.view
    record_hz = float(view.library.world_info(world).record_hz)
    grid = layout.grid_flow(row_major=True, columns=columns, even_columns=True, align=True)
    for frame in posing.filmstrip_frames(view.library.frame_count(world), FRAMES):
        cell = grid.column(align=True)
        icon = THUMBNAILS.icon(context.scene, world, frame)
        if icon:
            cell.template_icon(icon_value=icon, scale=scale)
        else:
            cell.label(icon="TIME")
        cell.label(text=f"{frame / record_hz:.1f} s")


def draw_filmstrip(layout, context):
    """The selected world's filmstrip under the ranking (nothing when no world is selected)."""
    view = SESSION.view
    world = context.scene.mwb.selected_world
    if view is None or world not in view.world_indices:
        return
    if context.scene.camera is None:
        wrapped_labels(layout, context, "Thumbnails need a scene camera", "OUTLINER_OB_CAMERA")
        return
    box = layout.box()
    row = box.row()
    row.label(text=f"World {world}", icon="RENDER_ANIMATION")
    row.operator("mwb.show_filmstrip", text="", icon="FULLSCREEN_ENTER").world = world
    draw_frames(box, context, world, SCALE, SIDEBAR_COLUMNS)


class MWB_OT_show_filmstrip(bpy.types.Operator):
    """Show the world's filmstrip large: the scene from its camera from the world's start to its rest"""
    bl_idname = "mwb.show_filmstrip"
    bl_label = "Filmstrip"

    world: bpy.props.IntProperty(name="World", default=-1)

    @classmethod
    def poll(cls, context):
        return SESSION.view is not None and context.scene.camera is not None

    def invoke(self, context, event):
        if self.world not in SESSION.view.world_indices:
            self.world = context.scene.mwb.selected_world
        if self.world not in SESSION.view.world_indices:
            return {"CANCELLED"}
        scale = context.preferences.view.ui_scale
        return context.window_manager.invoke_popup(self, width=int(FRAMES * POPUP_FRAME_PIXELS * scale))

    def draw(self, context):
        if SESSION.view is None or self.world not in SESSION.view.world_indices:
            return
        self.layout.label(text=f"World {self.world}", icon="RENDER_ANIMATION")
        draw_frames(self.layout, context, self.world, POPUP_SCALE)

    def execute(self, context):
        return {"FINISHED"}


classes = (MWB_OT_show_filmstrip,)
