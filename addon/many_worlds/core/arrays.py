"""Array shaping between the library's numpy arrays and what drawing and baking need."""
import numpy as np


def polyline_segments(polyline, bodies):
    """Line-list vertices of the given bodies' paths.

    polyline: float32 (bodies, points, 3). bodies: indices to draw.
    Returns float32 (segments * 2, 3), consecutive pairs are one segment (the 'LINES' primitive
    draws many disjoint paths in one batch).
    """
    if len(bodies) == 0 or polyline.shape[1] < 2:
        return np.zeros((0, 3), np.float32)
    paths = polyline[np.asarray(bodies, dtype=np.intp)]
    starts = paths[:, :-1, :]
    ends = paths[:, 1:, :]
    return np.stack([starts, ends], axis=2).reshape(-1, 3).astype(np.float32, copy=False)


def world_frame_of_scene_frame(scene_frame, frame_start, fps, record_hz):
    """Fractional recorded frame of a (sub)frame of the Blender scene; world time 0 is frame_start."""
    return (np.asarray(scene_frame, dtype=np.float64) - frame_start) / fps * record_hz


def bake_scene_frames(frame_start, fps, record_hz, frame_count):
    """Integer scene frames covered by a world of frame_count recorded frames, one key per frame."""
    duration_s = (frame_count - 1) / record_hz
    last = int(np.floor(duration_s * fps + 1e-9))
    return np.arange(frame_start, frame_start + last + 1)


def continuous_quaternions(q):
    """Flip signs so consecutive (w, x, y, z) quaternions have a non-negative dot product.

    q and -q are the same rotation, but keys that alternate sign make F-curves swing the long way.
    q: (..., frames, 4).
    """
    q = np.array(q, dtype=np.float64, copy=True)
    dots = np.sum(q[..., 1:, :] * q[..., :-1, :], axis=-1)
    flips = np.cumsum(dots < 0, axis=-1) % 2 == 1
    q[..., 1:, :][flips] *= -1
    return q


def sample_tracks(positions, orientations, world_frames):
    """Positions and orientations at fractional recorded frames (linear and normalized-linear).

    positions: (bodies, frames, 3); orientations: (bodies, frames, 4) (w, x, y, z).
    world_frames: (n,) fractional indices, clamped to the recorded range.
    Returns (bodies, n, 3) and (bodies, n, 4), quaternions sign-continuous.
    """
    frame_count = positions.shape[1]
    f = np.clip(np.asarray(world_frames, dtype=np.float64), 0, frame_count - 1)
    lo = np.floor(f).astype(np.intp)
    hi = np.minimum(lo + 1, frame_count - 1)
    u = (f - lo)[None, :, None]
    loc = positions[:, lo] * (1 - u) + positions[:, hi] * u
    q = continuous_quaternions(orientations)
    rot = q[:, lo] * (1 - u) + q[:, hi] * u
    rot /= np.linalg.norm(rot, axis=-1, keepdims=True)
    return loc, rot


def fcurve_points(frames, values):
    """Flat [f0, v0, f1, v1, ...] float32 for FCurve.keyframe_points.foreach_set('co', ...)."""
    co = np.empty((len(frames), 2), np.float32)
    co[:, 0] = frames
    co[:, 1] = values
    return co.ravel()
