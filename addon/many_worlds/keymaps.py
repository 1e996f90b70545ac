"""Input bindings of the box tool: a keymap item and a toolbar tool in the 3D Viewport.

Ctrl+Alt+left-drag draws a positive box and Ctrl+Alt+Shift+left-drag a negative one, in Object
Mode (Blender's default keymap binds that chord only in Grease Pencil, Mask, Clip and Node
editors and mesh Edit Mode, so Object Mode is free). The "Query Box" toolbar tool binds plain
left-drag and Shift+left-drag the same way.

Alt+Down and Alt+Up preview the next and the previous world of the ranking. They sit in the
"Frames" keymap, beside the playback keys, so they work over any editor and while the timeline
plays (Blender binds Alt+Up/Down only in text editing and the file browser, which keep them).
"""
import bpy

classes = ()

_ITEMS = []
_TOOL = []


class MWB_WT_query_box(bpy.types.WorkSpaceTool):
    bl_space_type = "VIEW_3D"
    bl_context_mode = "OBJECT"
    bl_idname = "mwb.query_box_tool"
    bl_label = "Query Box"
    bl_description = ("Drag a box over the paths: keep the worlds whose paths enter it.\n"
                      "Shift+drag: keep the worlds whose paths stay out of it")
    bl_icon = "ops.generic.select_box"
    bl_widget = None
    bl_keymap = (
        ("mwb.draw_box", {"type": "LEFTMOUSE", "value": "CLICK_DRAG"}, {"properties": [("negative", False)]}),
        ("mwb.draw_box", {"type": "LEFTMOUSE", "value": "CLICK_DRAG", "shift": True},
         {"properties": [("negative", True)]}),
    )


def add():
    keyconfig = bpy.context.window_manager.keyconfigs.addon
    # Background Blender has no add-on key configuration; there is nothing to bind there.
    if keyconfig is not None and not _ITEMS:
        keymap = keyconfig.keymaps.new(name="Object Mode", space_type="EMPTY")
        for shift in (False, True):
            item = keymap.keymap_items.new("mwb.draw_box", "LEFTMOUSE", "CLICK_DRAG", ctrl=True, alt=True, shift=shift)
            item.properties.negative = shift
            _ITEMS.append((keymap, item))
        keymap = keyconfig.keymaps.new(name="Frames", space_type="EMPTY")
        for key, step in (("DOWN_ARROW", 1), ("UP_ARROW", -1)):
            item = keymap.keymap_items.new("mwb.step_world", key, "PRESS", alt=True)
            item.properties.step = step
            _ITEMS.append((keymap, item))
    if not _TOOL:
        bpy.utils.register_tool(MWB_WT_query_box, separator=True)
        _TOOL.append(MWB_WT_query_box)


def remove():
    while _ITEMS:
        keymap, item = _ITEMS.pop()
        keymap.keymap_items.remove(item)
    while _TOOL:
        bpy.utils.unregister_tool(_TOOL.pop())
