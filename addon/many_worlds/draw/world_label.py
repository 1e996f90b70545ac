"""The viewport's label of the previewed world, bottom-left in the 3D view's region: its index,
when it came to rest, and how many of the goal's enabled parts (boxes and poses) it meets, under
a line saying the scene is in preview (or which edit waits for the user to end it). Drawn only
while a world is selected."""
import blf
import bpy

from .. import preview, scene_boxes
from ..core import library_query
from ..core.session import SESSION
from .overlay import ViewportOverlay
from .paths import SELECTED_COLOR

FONT_ID = 0
FONT_SIZE = 16
MARGIN = 16        # pixels at UI scale 1 from the region's left (past the toolbar) and bottom edges
STATE_FONT_SIZE = 12
STATE_COLOR = (0.9, 0.9, 0.9, 1.0)
CONFLICT_COLOR = (1.0, 0.55, 0.1, 1.0)


def label_text(context):
    """The label of the selected world, or "" when none is selected or no library is open."""
    view = SESSION.view
    settings = context.scene.mwb
    world = settings.selected_world
    if view is None or world < 0:
        return ""
    try:
        row = view.world_indices.index(world)
    except ValueError:
        return ""
    rest_s = settings.worlds[row].rest_s if row < len(settings.worlds) else view.world_summary(world)["rest_s"]
    lq = SESSION.query if SESSION.query is not None and SESSION.query.view is view else None
    result = lq.result if lq is not None else None
    if result is None or not result.box_count or row >= len(result.boxes_satisfied):
        return library_query.world_label_text(world, rest_s)
    return library_query.world_label_text(world, rest_s, int(result.boxes_satisfied[row]), result.box_count)


def label_origin(context):
    """(x, y) of the label's baseline in region pixels: above the bottom edge, right of the toolbar
    when the toolbar overlaps the viewport."""
    scale = context.preferences.view.ui_scale
    x = y = MARGIN * scale
    area = context.area
    if area is not None and context.preferences.system.use_region_overlap:
        tools = next((r for r in area.regions if r.type == "TOOLS"), None)
        if tools is not None and tools.width > 1:
            x += tools.width
    return x, y


class WorldLabel(ViewportOverlay):
    def draw(self):
        context = bpy.context
        text = label_text(context)
        if not text:
            return
        scale = context.preferences.view.ui_scale
        x, y = label_origin(context)
        blf.size(FONT_ID, FONT_SIZE * scale)
        blf.color(FONT_ID, *SELECTED_COLOR)
        blf.enable(FONT_ID, blf.SHADOW)
        blf.shadow(FONT_ID, 3, 0.0, 0.0, 0.0, 0.8)
        blf.shadow_offset(FONT_ID, 1, -1)
        blf.position(FONT_ID, x, y, 0)
        try:
            blf.draw(FONT_ID, text)
            state = preview.state_text(context.scene)
            if state:
                blf.size(FONT_ID, STATE_FONT_SIZE * scale)
                blf.color(FONT_ID, *(CONFLICT_COLOR if preview.conflict(context.scene) else STATE_COLOR))
                blf.position(FONT_ID, x, y + (FONT_SIZE + 8) * scale, 0)
                blf.draw(FONT_ID, state)
        finally:
            blf.disable(FONT_ID, blf.SHADOW)


OVERLAY = WorldLabel()
