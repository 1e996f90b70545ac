"""Preview: pose the scene's simulated objects from the selected world as the timeline moves.

While previewing, the scene's rigid body world is switched off so Blender's own cache does not
move the objects as well, and each object's own transform is saved in the scene (so even a saved
and reopened file can be restored). `end` puts everything back.
"""
import bpy
from mathutils import Matrix, Quaternion, Vector

from .core import arrays
from .core.session import SESSION


def _objects_by_body(view):
    """(body index, object) of the simulated bodies that exist in this file."""
    out = []
    for i in view.simulated_bodies():
        ob = bpy.data.objects.get(view.body_names[i])
        if ob is not None:
            out.append((i, ob))
    return out


def begin(scene):
    """Start (or switch) the preview to scene.mwb.selected_world and pose the current frame."""
    settings = scene.mwb
    view = SESSION.view
    if view is None or settings.selected_world not in view.world_indices:
        return False
    if not settings.previewing:
        settings.preview_saved.clear()
        for _, ob in _objects_by_body(view):
            item = settings.preview_saved.add()
            item.target = ob
            item.matrix_basis = [v for row in ob.matrix_basis for v in row]
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
    if not settings.previewing or view is None or settings.selected_world not in view.world_indices:
        return
    if frame is None:
        frame = scene.frame_current + scene.frame_subframe
    positions, orientations, record_hz = view.decoded(settings.selected_world)
    world_frame = arrays.world_frame_of_scene_frame([frame], view.frame_start, view.fps, record_hz)
    loc, rot = arrays.sample_tracks(positions, orientations, world_frame)
    for i, ob in _objects_by_body(view):
        scale = ob.matrix_world.to_scale()
        ob.matrix_world = Matrix.LocRotScale(Vector(loc[i, 0]), Quaternion(rot[i, 0]), scale)


def end(scene):
    """Stop previewing: restore the objects' own transforms and the rigid body world."""
    settings = scene.mwb
    if not settings.previewing:
        return False
    for item in settings.preview_saved:
        if item.target is not None:
            m = item.matrix_basis
            item.target.matrix_basis = Matrix([m[0:4], m[4:8], m[8:12], m[12:16]])
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
