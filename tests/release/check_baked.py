"""Inside Blender, on a .blend that `many_worlds bake` wrote: every simulated (active) object is
keyframed over the world's frames and switched to Animated, so the simulation no longer moves it,
and with the rigid body world switched off the keys alone move the objects.

    blender -b BAKED.blend --python-exit-code 1 --python tests/release/check_baked.py
"""
import os
import sys

import bpy
from mathutils import Vector

# The compatibility module of this checkout's add-on reads keys on every Blender (slotted or not).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "addon"))
from many_worlds import compat  # noqa: E402

active = [o for o in bpy.context.scene.objects if o.rigid_body and o.rigid_body.type == "ACTIVE"]
assert active, "the baked file has no active rigid bodies"
for obj in active:
    frames = {int(k.co.x) for fc in compat.object_fcurves(obj) for k in fc.keyframe_points}
    assert len(frames) > 10, f"{obj.name} has keyframes on only {len(frames)} frames"
    assert obj.rigid_body.kinematic, f"{obj.name} is not Animated, so the simulation would override its keys"
# The keys alone move them: with the rigid body world off, every keyed object is where its keys
# put it, and the world's objects are not all standing still.
scene = bpy.context.scene
scene.rigidbody_world.enabled = False
first, last = scene.frame_start, max(int(k.co.x) for fc in compat.object_fcurves(active[0]) for k in fc.keyframe_points)
scene.frame_set(first)
start = {obj.name: obj.matrix_world.translation.copy() for obj in active}
scene.frame_set(last)
moved = [obj.name for obj in active if (obj.matrix_world.translation - start[obj.name]).length > 0.05]
assert moved, f"with the rigid body world off, no baked object moves between frames {first} and {last}"
for obj in active:
    keyed = Vector([compat.find_fcurve(obj, "location", k).evaluate(last) for k in range(3)])
    assert (obj.matrix_world.translation - keyed).length < 1e-4, f"{obj.name} is not where its keys put it"
print(f"release: baked file keys all {len(active)} simulated objects ({', '.join(o.name for o in active)})")
