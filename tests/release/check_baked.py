"""Inside Blender, on a .blend that `many_worlds bake` wrote: every simulated (active) object is
keyframed over the world's frames and switched to Animated, so the simulation no longer moves it.

    blender -b BAKED.blend --python-exit-code 1 --python tests/release/check_baked.py
"""
import bpy

active = [o for o in bpy.context.scene.objects if o.rigid_body and o.rigid_body.type == "ACTIVE"]
assert active, "the baked file has no active rigid bodies"
for obj in active:
    action = obj.animation_data.action if obj.animation_data else None
    frames = {int(k.co.x) for fc in action.fcurves for k in fc.keyframe_points} if action else set()
    assert len(frames) > 10, f"{obj.name} has keyframes on only {len(frames)} frames"
    assert obj.rigid_body.kinematic, f"{obj.name} is not Animated, so the simulation would override its keys"
print(f"release: baked file keys all {len(active)} simulated objects ({', '.join(o.name for o in active)})")
