"""Bake the selected world to keyframes.

One key per scene frame: world time 0 is the rigid body world's first frame, so scene frame f
shows world time (f - frame_start) / fps (positions interpolated between the 120 Hz records when
fps does not divide 120). Keys run to the world's last recorded frame and hold after it.
Rotations are written as quaternions (the object's rotation_mode becomes 'QUATERNION'): Euler
keys interpolate differently between frames and can flip at +-180 degrees.
The baked objects keep their rigid bodies, switched to "Animated" so the keys rule (Blender's
"Bake To Keyframes" removes them instead): the scene still samples as it was set up.

An object whose body does not exist in the baked world (removed from it, or added only to other
worlds) would otherwise stand still or be simulated by Blender among the baked objects; the bake
hides it instead, with keys on hide_viewport and hide_render (shown until the frame before the
simulation starts, hidden from its first frame on), and hands it to the keys like the baked ones if
the simulation moved it. Baking a world it exists in removes those keys again and shows it. Objects
that are not bodies of the library are left alone.
"""
from dataclasses import dataclass
from typing import List

import bpy
import numpy as np

from . import compat, preview
from .core import arrays
from .export import PREBAKE_MATRIX
from .core.session import SESSION

GROUP = "Object Transforms"
# Hide keys of the bake, told apart from the user's own by their group.
VISIBILITY_GROUP = "Many Worlds Visibility"
VISIBILITY_PATHS = ("hide_viewport", "hide_render")


def _write_channel(ob, data_path, index, frames, values, group=GROUP):
    """Key ob's data_path[index] at frames; its other channels (a keyed scale, a custom property)
    stay as the animator keyed them."""
    fcurve = compat.new_fcurve(ob, data_path, index, group)
    # The bulk path: one allocation and one array copy instead of a keyframe_insert per frame.
    fcurve.keyframe_points.add(len(frames))
    fcurve.keyframe_points.foreach_set("co", arrays.fcurve_points(frames, values))
    fcurve.update()
    return fcurve


def animation_warnings(objects, users):
    """One sentence per object whose keys other objects play too (users: compat.AnimationUsers)."""
    warnings = []
    for ob in objects:
        others = users.others(ob)
        if others:
            names = ", ".join(o.name for o in others)
            warnings.append(f"{ob.name}: its animation is shared with {names}; "
                            f"baking it gives {ob.name} an action of its own")
    return warnings


def _own_action(ob, action_suffix, users):
    """ob's action, made its own first if other objects play the same keys (they keep theirs)."""
    if users.others(ob):
        users.leave(ob)
        ob.animation_data.action = ob.animation_data.action.copy()
    return compat.ensure_action(ob, f"{ob.name}{action_suffix}")


def bake_objects(objects, frames, locations, rotations, action_suffix="MWB", users=None):
    """Key objects[i] at frames with locations[i] (n, 3) and quaternions rotations[i] (n, 4)."""
    users = compat.AnimationUsers(bpy.data.objects) if users is None else users
    for ob, loc, rot in zip(objects, locations, rotations):
        _own_action(ob, action_suffix, users)
        ob.rotation_mode = "QUATERNION"
        for k in range(3):
            _write_channel(ob, "location", k, frames, loc[:, k])
        for k in range(4):
            _write_channel(ob, "rotation_quaternion", k, frames, rot[:, k])


def _remove_visibility_keys(ob):
    """Remove hide keys an earlier bake wrote (the user's own stay) and show the object again."""
    for path in VISIBILITY_PATHS:
        fcurve = compat.find_fcurve(ob, path, 0)
        if fcurve is not None and fcurve.group is not None and fcurve.group.name == VISIBILITY_GROUP:
            compat.remove_fcurve(ob, fcurve)
            # The keys last set the property; without them it would stay as they left it.
            setattr(ob, path, False)


def hide_objects(objects, frame_start, action_suffix="MWB", users=None):
    """Key the objects shown up to frame_start - 1 and hidden from frame_start on (viewport and render)."""
    users = compat.AnimationUsers(bpy.data.objects) if users is None else users
    frames = np.array([frame_start - 1, frame_start], dtype=np.float64)
    for ob in objects:
        _own_action(ob, action_suffix, users)
        for path in VISIBILITY_PATHS:
            fcurve = _write_channel(ob, path, 0, frames, [0.0, 1.0], VISIBILITY_GROUP)
            for key in fcurve.keyframe_points:
                key.interpolation = "CONSTANT"


def remember_setup(context, objects):
    """Keep each object's transform from before its first bake (the one the user set up), for the
    export: the keys will move the object."""
    context.view_layer.update()  # a preview that just ended left matrix_world stale
    for ob in objects:
        if ob.rigid_body is not None and PREBAKE_MATRIX not in ob:
            ob[PREBAKE_MATRIX] = [v for row in ob.matrix_world for v in row]


def hand_to_keys(objects):
    """Let the keys move the objects: their rigid bodies become "Animated" (Blender's simulation
    follows the keys and other bodies still collide with them), and each keeps its settings and
    variation ranges, so Sample works after a bake as before it."""
    for ob in objects:
        if ob.rigid_body is not None:
            ob.rigid_body.kinematic = True


def _objects_of(view, bodies):
    """(body index, object) of the bodies whose objects exist in this file."""
    pairs = [(i, bpy.data.objects.get(view.body_names[i])) for i in bodies]
    return [(i, ob) for i, ob in pairs if ob is not None]


@dataclass
class BakeOutcome:
    """What a bake did, by object name."""
    baked: List[str]
    hidden: List[str]        # objects the world does not have, keyed hidden
    skipped: List[str]       # bodies of the world whose objects are gone from the file
    to_quaternion: List[str]  # objects whose rotation mode the bake set to Quaternion
    warnings: List[str]

    def text(self, world):
        """The one line a person reads: what was baked, hidden, skipped and changed."""
        parts = [f"Baked world {world} onto {len(self.baked)} objects"]
        if self.hidden:
            parts.append(f"hid {len(self.hidden)} not in it ({', '.join(self.hidden)})")
        if self.skipped:
            parts.append(f"skipped {len(self.skipped)} no longer in the file ({', '.join(self.skipped)})")
        if self.to_quaternion:
            parts.append(f"set the rotation mode of {len(self.to_quaternion)} to Quaternion "
                         f"({', '.join(self.to_quaternion)})")
        return "; ".join(parts)


def bake_world(context, world):
    """Bake one world of the open library onto the scene's objects and hide the objects whose
    bodies it does not have. Returns a BakeOutcome."""
    view = SESSION.view
    record_hz = view.record_hz(world)
    # Keys run to the end of the run: a world that came to rest holds its last pose there.
    frames = arrays.bake_scene_frames(view.frame_start, view.fps, record_hz,
                                      max(view.library.frame_count(world), view.run_frame_count))
    world_frames = arrays.world_frame_of_scene_frame(frames, view.frame_start, view.fps, record_hz)
    present = view.present(world)
    simulated = view.simulated_bodies()
    pairs = _objects_of(view, view.present_bodies(world, simulated))
    skipped = sorted({view.body_names[i] for i in view.present_bodies(world, simulated)} -
                     {ob.name for _, ob in pairs})
    to_quaternion = [ob.name for _, ob in pairs if ob.rotation_mode != "QUATERNION"]
    # One body per object: the one the world has, if any (an updated object has several).
    every = _objects_of(view, view.object_bodies(world).values())
    absent = [ob for i, ob in every if not present[i]]
    absent_simulated = {view.body_names[i] for i in simulated if not present[i]}
    handed = [ob for _, ob in pairs] + [ob for ob in absent if ob.name in absent_simulated]
    remember_setup(context, handed)
    users = compat.AnimationUsers(bpy.data.objects)
    warnings = animation_warnings([ob for _, ob in pairs] + absent, users)
    if pairs:
        loc, rot = view.library.poses(world, world_frames, [i for i, _ in pairs])
        bake_objects([ob for _, ob in pairs], frames.astype(np.float64), loc, rot, users=users)
    for i, ob in every:
        if present[i]:
            _remove_visibility_keys(ob)
    hide_objects(absent, view.frame_start, users=users)
    hand_to_keys(handed)
    return BakeOutcome([ob.name for _, ob in pairs], [ob.name for ob in absent], skipped, to_quaternion, warnings)


class MWB_OT_bake_world(bpy.types.Operator):
    """Write the selected world as keyframes on its objects, whose rigid bodies follow the keys
    ("Animated"); objects not in the world are keyed hidden"""
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
        outcome = bake_world(context, world)
        for warning in outcome.warnings:
            self.report({"WARNING"}, warning)
        if not outcome.baked and not outcome.hidden:
            self.report({"WARNING"}, "No object of this world exists in the scene")
            return {"CANCELLED"}
        self.report({"WARNING"} if outcome.skipped else {"INFO"}, outcome.text(world))
        return {"FINISHED"}


classes = (MWB_OT_bake_world,)
