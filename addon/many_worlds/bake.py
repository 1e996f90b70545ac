"""Bake the selected world to keyframes.

One key per scene frame: world time 0 is the rigid body world's first frame, so scene frame f
shows world time (f - frame_start) / fps (positions interpolated between the 120 Hz records when
fps does not divide 120). Keys run to the world's last recorded frame and hold after it.
Rotations are written as quaternions (the object's rotation_mode becomes 'QUATERNION'): Euler
keys interpolate differently between frames and can flip at +-180 degrees.
Like Blender's "Bake To Keyframes", the baked objects lose their rigid body so the keys rule.
"""
import bpy
import numpy as np

from . import compat, preview
from .core import arrays
from .core.session import SESSION

GROUP = "Object Transforms"


def _write_channel(action, data_path, index, frames, values):
    fcurve = compat.find_fcurve(action, data_path, index)
    if fcurve is not None:
        action.fcurves.remove(fcurve)
    fcurve = compat.new_fcurve(action, data_path, index, GROUP)
    # The bulk path: one allocation and one array copy instead of a keyframe_insert per frame.
    fcurve.keyframe_points.add(len(frames))
    fcurve.keyframe_points.foreach_set("co", arrays.fcurve_points(frames, values))
    fcurve.update()


def bake_objects(objects, frames, locations, rotations, action_suffix="MWB"):
    """Key objects[i] at frames with locations[i] (n, 3) and quaternions rotations[i] (n, 4)."""
    for ob, loc, rot in zip(objects, locations, rotations):
        if ob.animation_data is None:
            ob.animation_data_create()
        action = ob.animation_data.action
        if action is None:
            action = bpy.data.actions.new(f"{ob.name}{action_suffix}")
            ob.animation_data.action = action
        ob.rotation_mode = "QUATERNION"
        for k in range(3):
            _write_channel(action, "location", k, frames, loc[:, k])
        for k in range(4):
            _write_channel(action, "rotation_quaternion", k, frames, rot[:, k])


def remove_rigid_bodies(context, objects):
    """Take the objects out of the simulation, as Blender's Bake To Keyframes does."""
    with compat.temp_override(context, selected_objects=list(objects), active_object=objects[0],
                              object=objects[0]):
        bpy.ops.rigidbody.objects_remove()


def bake_world(context, world):
    """Bake one world of the open library onto the scene's objects; returns the baked object names."""
    view = SESSION.view
    positions, orientations, record_hz = view.decoded(world)
    frames = arrays.bake_scene_frames(view.frame_start, view.fps, record_hz, positions.shape[1])
    world_frames = arrays.world_frame_of_scene_frame(frames, view.frame_start, view.fps, record_hz)
    loc, rot = arrays.sample_tracks(positions, orientations, world_frames)
    pairs = [(i, bpy.data.objects.get(view.body_names[i])) for i in view.simulated_bodies()]
    pairs = [(i, ob) for i, ob in pairs if ob is not None]
    if not pairs:
        return []
    index = np.array([i for i, _ in pairs])
    objects = [ob for _, ob in pairs]
    bake_objects(objects, frames.astype(np.float64), loc[index], rot[index])
    remove_rigid_bodies(context, objects)
    return [ob.name for ob in objects]


class MWB_OT_bake_world(bpy.types.Operator):
    """Write the selected world as keyframes on its objects and remove their rigid bodies"""
    bl_idname = "mwb.bake_world"
    bl_label = "Bake World"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        view = SESSION.view
        return view is not None and context.scene.mwb.selected_world in view.world_indices

    def execute(self, context):
        world = context.scene.mwb.selected_world
        # The preview moved the objects and switched the rigid body world off; put that back first.
        preview.end(context.scene)
        names = bake_world(context, world)
        if not names:
            self.report({"WARNING"}, "No object of this world exists in the scene")
            return {"CANCELLED"}
        self.report({"INFO"}, f"Baked world {world} onto {len(names)} objects")
        return {"FINISHED"}


classes = (MWB_OT_bake_world,)
