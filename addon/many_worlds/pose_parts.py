"""Pose parts and the objects in the file: which way a part's objects face now (at the frame
shown; while a world is previewed, that world's pose), and capturing the side of an object that
faces up as the pose to keep (As Posed). The directions themselves are core.pose_target's."""
import bpy
import numpy as np

from .core import pose_target


def object_rotation(ob):
    """The object's world rotation now (3x3, object to world, without its scale)."""
    return np.array(ob.matrix_world.to_3x3().normalized())


def directions(part):
    """(axis in the object's frame, target in the world) of a pose part, or None for an As Posed
    part with no captured side."""
    return pose_target.directions(part.pose_mode, part.pose_axis, part.pose_direction,
                                  tuple(part.pose_captured_axis))


def angles_now(part):
    """[(object name, degrees its axis is from the part's direction now)] for the part's objects in
    the file (empty for an As Posed part with no captured side)."""
    wanted = directions(part)
    if wanted is None:
        return []
    objects = [bpy.data.objects[item.name] for item in part.bodies if item.name in bpy.data.objects]
    return [(ob.name, pose_target.angle_deg(object_rotation(ob), *wanted)) for ob in objects]


def capture(part):
    """Store in a pose part the side of its first object that faces up now, without evaluating the
    goal (the caller does). False when none of its objects is in the file."""
    ob = next((bpy.data.objects[item.name] for item in part.bodies if item.name in bpy.data.objects), None)
    if ob is None:
        return False
    part["pose_captured_axis"] = pose_target.captured_axis(object_rotation(ob))
    return True
