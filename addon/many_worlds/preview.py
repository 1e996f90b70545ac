"""Preview: pose the scene's simulated objects from the selected world as the timeline moves.

While previewing, the scene's rigid body world is switched off so Blender's own cache does not
move the objects as well, and each object's own transform is saved in the scene (so even a saved
and reopened file can be restored). An object whose body does not exist in the previewed world
(removed from it, or added only to other worlds) stays where it is, drawn as wire, so it can still
be selected (to add it to the world, say). `end` puts everything back.
"""
import bpy
from mathutils import Matrix, Quaternion, Vector

from .core import arrays
from .core.session import SESSION

ABSENT_DISPLAY = "WIRE"


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
    apply(scene)
    return True


def apply(scene, frame=None):
    """Pose the simulated objects at `frame` (default: the current frame and subframe)."""
    settings = scene.mwb
    view = SESSION.view
    world = settings.selected_world
    if not settings.previewing or view is None or world not in view.world_indices:
        return
    if frame is None:
        frame = scene.frame_current + scene.frame_subframe
    positions, orientations, record_hz = view.decoded(world)
    world_frame = arrays.world_frame_of_scene_frame([frame], view.frame_start, view.fps, record_hz)
    loc, rot = arrays.sample_tracks(positions, orientations, world_frame)
    present = view.present(world)
    simulated = set(view.simulated_bodies())
    saved = _saved_items(settings)
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
    if scene.rigidbody_world is not None:
        scene.rigidbody_world.enabled = settings.preview_rigidbody_enabled
    settings.previewing = False
    return True


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
    """Stop previewing the selected world and restore the scene as it was"""
    bl_idname = "mwb.end_preview"
    bl_label = "End Preview"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.scene.mwb.previewing

    def execute(self, context):
        end(context.scene)
        return {"FINISHED"}


classes = (MWB_OT_end_preview,)
