"""The directions of a pose part, without bpy: which side of an object it tests and which world
direction that side should face, as the sidebar names them, and how far an object is from it.

A pose part holds an object's own `axis` (a direction in its local frame) within a tolerance of
a world direction `target`. The sidebar offers three ways to say which:
  UPRIGHT:   the object's local +Z towards world up;
  AXIS:      one of the object's axes (±X, ±Y, ±Z) towards one world direction (±X, ±Y, ±Z);
  AS_POSED:  the side of the object facing up when the part was captured stays up.
"""
import numpy as np

UPRIGHT, AXIS, AS_POSED = "UPRIGHT", "AXIS", "AS_POSED"

# Each enum item: (identifier, label, unit vector). The order is the sidebar's and is saved by
# position in .blend files: append, never reorder.
DIRECTIONS = (("POS_X", "+X", (1.0, 0.0, 0.0)), ("NEG_X", "-X", (-1.0, 0.0, 0.0)),
              ("POS_Y", "+Y", (0.0, 1.0, 0.0)), ("NEG_Y", "-Y", (0.0, -1.0, 0.0)),
              ("POS_Z", "+Z", (0.0, 0.0, 1.0)), ("NEG_Z", "-Z", (0.0, 0.0, -1.0)))
VECTORS = {name: vector for name, _, vector in DIRECTIONS}
LABELS = {name: label for name, label, _ in DIRECTIONS}
UP = (0.0, 0.0, 1.0)


def captured_axis(rotation):
    """The side of an object that faces world up while it has `rotation` (3x3, object to world,
    without scale): R⁻¹·(0, 0, 1) in the object's own frame, a unit vector."""
    r = np.asarray(rotation, dtype=np.float64).reshape(3, 3)
    axis = r.T @ np.array(UP)
    return tuple(float(v) for v in axis / np.linalg.norm(axis))


def directions(mode, object_axis="POS_Z", world_direction="POS_Z", captured=(0.0, 0.0, 0.0)):
    """(axis in the object's frame, target in the world) of a part, or None when an As Posed part
    has no captured axis yet."""
    if mode == UPRIGHT:
        return UP, UP
    if mode == AXIS:
        return VECTORS[object_axis], VECTORS[world_direction]
    if not any(captured):
        return None
    return tuple(float(v) for v in captured), UP


def angle_deg(rotation, axis, target):
    """Degrees between the object's `axis` turned by `rotation` (3x3, object to world) and the
    world direction `target` (both of any length)."""
    r = np.asarray(rotation, dtype=np.float64).reshape(3, 3)
    turned = r @ np.asarray(axis, dtype=np.float64)
    target = np.asarray(target, dtype=np.float64)
    cos = turned @ target / (np.linalg.norm(turned) * np.linalg.norm(target))
    return float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


def describe(mode, object_axis="POS_Z", world_direction="POS_Z", captured=(0.0, 0.0, 0.0)):
    """(side, direction) of a part in words: ('local +Z', 'up'), ('local -X', '+Y'), ('captured
    side (0.00, -1.00, 0.00)', 'up'); side is None for an As Posed part with no captured side."""
    if mode == UPRIGHT:
        return "local +Z", "up"
    if mode == AXIS:
        return f"local {LABELS[object_axis]}", LABELS[world_direction]
    if not any(captured):
        return None, "up"
    return "captured side (" + ", ".join(f"{round(v, 2) + 0.0:.2f}" for v in captured) + ")", "up"


def cone_segments(origin, target, within_deg, length, circle_segments=32, generators=4):
    """Line segments, as consecutive pairs of points ((n, 3) array), of the cone of directions
    within `within_deg` of `target` with its apex at `origin`: its axis, `length` long; the circle
    where its surface is `length` from the apex; and `generators` lines from the apex to that
    circle, evenly spread."""
    origin = np.asarray(origin, dtype=np.float64)
    d = np.asarray(target, dtype=np.float64)
    d = d / np.linalg.norm(d)
    helper = np.array((1.0, 0.0, 0.0)) if abs(d[0]) < 0.9 else np.array((0.0, 1.0, 0.0))
    u = np.cross(d, helper)
    u /= np.linalg.norm(u)
    v = np.cross(d, u)
    half = np.radians(within_deg)
    angles = np.linspace(0.0, 2.0 * np.pi, circle_segments + 1)
    circle = (origin + d * length * np.cos(half)
              + length * np.sin(half) * (np.outer(np.cos(angles), u) + np.outer(np.sin(angles), v)))
    points = [origin, origin + d * length]
    for k in range(circle_segments):
        points += [circle[k], circle[k + 1]]
    for k in range(generators):
        points += [origin, circle[k * circle_segments // generators]]
    return np.array(points)
