"""Preview: pose the scene's simulated objects from the selected world as the timeline moves.

Preview is a state the user sees (the viewport label and the panel say so): the scene's rigid body
world is paused so Blender's own cache does not move the objects as well, and each object's own
transform is saved in the scene (so even a saved and reopened file can be restored). An object
whose body does not exist in the previewed world (removed from it, or added only to other worlds)
stays where it is, drawn as wire, so it can still be selected (to add it to the world, say). `end`
puts everything back.

An edit that the preview would undo (moving a posed object, switching the rigid body world back
on) is not undone behind the user's back: posing stops, and the user is asked to end the preview
(which restores the scene as it was before it) or to keep previewing (which poses the world again).
A rigid body world switched on during the preview stays on when it ends.
"""
import bpy
from mathutils import Matrix, Quaternion, Vector

from .core import arrays
from .core.session import SESSION

ABSENT_DISPLAY = "WIRE"
# Matrices closer than this (per element) are the same pose: what the preview set, read back.
SAME_POSE = 1e-4

# Per scene name: what the preview last posed (object name -> matrix_basis) and, once the user
# changed something the preview owns, the sentence saying what (posing stops until they choose).
_POSED = {}
CONFLICTS = {}


def conflict(scene):
    """The edit made during this scene's preview that waits for End Preview or Keep Previewing, or ''."""
    return CONFLICTS.get(scene.name, "") if scene.mwb.previewing else ""


def state_text(scene):
    """What the preview does to the scene, for the viewport label and the panel, or ''."""
    settings = scene.mwb
    if not settings.previewing:
        return ""
    if conflict(scene):
        return conflict(scene)
    rbw = "Rigid Body World paused, " if scene.rigidbody_world is not None else ""
    return f"Previewing world {settings.selected_world}: {rbw}End Preview to edit"


def _objects_by_body(view, world):
    """(body index, object) per library object that exists in this file: the body `world` has, or
    one it lacks."""
    out = []
    for name, i in view.object_bodies(world).items():
        ob = bpy.data.objects.get(name)
        if ob is not None:
            out.append((i, ob))
    return out


def _saved_items(settings):
    return {item.target.name: item for item in settings.preview_saved if item.target is not None}


def _save(settings, saved, ob):
    """Remember the object's own transform and display before the preview first changes it."""
    if ob.name not in saved:
        item = settings.preview_saved.add()
        item.target = ob
        item.matrix_basis = [v for row in ob.matrix_basis for v in row]
        item.display_type = ob.display_type
        saved[ob.name] = item
    return saved[ob.name]


def own_matrix(scene, ob):
    """The object's own transform (matrix_basis): from before the preview while it poses the object."""
    item = _saved_items(scene.mwb).get(ob.name) if scene.mwb.previewing else None
    return _saved_matrix(item) if item is not None and not item.restored else ob.matrix_basis


def _saved_matrix(item):
    m = item.matrix_basis
    return Matrix([m[0:4], m[4:8], m[8:12], m[12:16]])


def begin(scene):
    """Start (or switch) the preview to scene.mwb.selected_world and pose the current frame."""
    settings = scene.mwb
    view = SESSION.view
    if view is None or settings.selected_world not in view.world_indices:
        return False
    if not settings.previewing:
        settings.preview_saved.clear()
        rbw = scene.rigidbody_world
        settings.preview_rigidbody_enabled = rbw.enabled if rbw is not None else True
        if rbw is not None:
            rbw.enabled = False
        settings.previewing = True
    CONFLICTS.pop(scene.name, None)
    apply(scene)
    return True


def apply(scene, frame=None):
    """Pose the simulated objects at `frame` (default: the current frame and subframe)."""
    settings = scene.mwb
    view = SESSION.view
    world = settings.selected_world
    if not settings.previewing or view is None or world not in view.world_indices or conflict(scene):
        return
    if frame is None:
        frame = scene.frame_current + scene.frame_subframe
    world_frame = arrays.world_frame_of_scene_frame([frame], view.frame_start, view.fps, view.record_hz(world))
    loc, rot = view.library.poses(world, world_frame)
    present = view.present(world)
    simulated = set(view.simulated_bodies())
    saved = _saved_items(settings)
    posed = _POSED.setdefault(scene.name, {})
    posed.clear()
    for i, ob in _objects_by_body(view, world):
        item = saved.get(ob.name)
        if not present[i]:
            _show_absent(settings, saved, item, ob)
            continue
        if item is not None and item.display_type and ob.display_type != item.display_type:
            ob.display_type = item.display_type
        if i in simulated:
            item = _save(settings, saved, ob)
            if item.restored:
                # Absent from the last world shown, so the user may have moved it: its own transform now.
                item.matrix_basis = [v for row in ob.matrix_basis for v in row]
                item.restored = False
            scale = ob.matrix_world.to_scale()
            ob.matrix_world = Matrix.LocRotScale(Vector(loc[i, 0]), Quaternion(rot[i, 0]), scale)
            posed[ob.name] = ob.matrix_basis.copy()


def _show_absent(settings, saved, item, ob):
    """An object whose body the world lacks: at its own transform, drawn as wire."""
    if item is None:
        item = _save(settings, saved, ob)
        item.restored = True
    elif not item.restored:
        # Posed by the world shown before: back where the user had it.
        ob.matrix_basis = _saved_matrix(item)
        item.restored = True
    if ob.display_type != ABSENT_DISPLAY:
        ob.display_type = ABSENT_DISPLAY


def end(scene):
    """Stop previewing: restore the objects' own transforms and display, and the rigid body world."""
    settings = scene.mwb
    if not settings.previewing:
        return False
    for item in settings.preview_saved:
        if item.target is not None:
            if not item.restored:
                item.target.matrix_basis = _saved_matrix(item)
            if item.display_type:
                item.target.display_type = item.display_type
    settings.preview_saved.clear()
    rbw = scene.rigidbody_world
    if rbw is not None:
        # On now means the user switched it on during the preview: it stays on.
        rbw.enabled = rbw.enabled or settings.preview_rigidbody_enabled
    settings.previewing = False
    _POSED.pop(scene.name, None)
    CONFLICTS.pop(scene.name, None)
    return True


def forget():
    """Drop what the preview posed and asked: another file is open."""
    _POSED.clear()
    CONFLICTS.clear()


def _moved(ob, pose):
    return any(abs(a - b) > SAME_POSE for row, posed_row in zip(ob.matrix_basis, pose)
               for a, b in zip(row, posed_row))


def find_conflict(scene):
    """The sentence naming an edit the preview would undo, or '': a posed object moved, or the
    rigid body world switched on."""
    rbw = scene.rigidbody_world
    if rbw is not None and rbw.enabled:
        return "The Rigid Body World was switched on: End Preview to simulate, or Keep Previewing"
    posed = _POSED.get(scene.name, {})
    moved = [name for name, pose in posed.items()
             if bpy.data.objects.get(name) is not None and _moved(bpy.data.objects[name], pose)]
    if moved:
        return f"{', '.join(moved)} moved: End Preview, then edit (the move is undone), or Keep Previewing"
    return ""


def check_edits(scene):
    """Stop posing when the user changed what the preview owns, and ask them what to do once."""
    if not scene.mwb.previewing or conflict(scene):
        return
    text = find_conflict(scene)
    if not text:
        return
    CONFLICTS[scene.name] = text
    if not bpy.app.background:
        bpy.app.timers.register(_ask_to_end, first_interval=0.0)
    _tag_redraw()


def _ask_to_end():
    wm = bpy.context.window_manager
    scene = bpy.context.scene
    if wm is None or not wm.windows or not conflict(scene):
        return None
    text = conflict(scene)

    def draw(menu, _context):
        layout = menu.layout
        layout.label(text=text, icon="ERROR")
        layout.operator("mwb.end_preview", icon="LOOP_BACK")
        layout.operator("mwb.keep_previewing", icon="PLAY")

    with bpy.context.temp_override(window=wm.windows[0]):
        wm.popup_menu(draw, title="Editing during preview", icon="QUESTION")
    return None


def _tag_redraw():
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else []):
        for area in window.screen.areas:
            area.tag_redraw()


@bpy.app.handlers.persistent
def on_depsgraph_update(scene, depsgraph=None):
    if scene.mwb.previewing:
        check_edits(scene)


@bpy.app.handlers.persistent
def on_frame_change(scene, depsgraph=None):
    # frame_change_pre: the new frame is set but not yet evaluated, so the posed transforms are
    # what this frame draws.
    if scene.mwb.previewing:
        apply(scene)


def end_all_previews():
    for scene in bpy.data.scenes:
        end(scene)


class MWB_OT_end_preview(bpy.types.Operator):
    """Stop previewing: objects back where they were before the preview, and the Rigid Body World as it was"""
    bl_idname = "mwb.end_preview"
    bl_label = "End Preview"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.scene.mwb.previewing

    def execute(self, context):
        end(context.scene)
        return {"FINISHED"}


class MWB_OT_keep_previewing(bpy.types.Operator):
    """Pose the previewed world again, undoing the edit made during the preview"""
    bl_idname = "mwb.keep_previewing"
    bl_label = "Keep Previewing"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return bool(conflict(context.scene))

    def execute(self, context):
        scene = context.scene
        CONFLICTS.pop(scene.name, None)
        if scene.rigidbody_world is not None:
            scene.rigidbody_world.enabled = False
        apply(scene)
        return {"FINISHED"}


classes = (MWB_OT_end_preview, MWB_OT_keep_previewing)
