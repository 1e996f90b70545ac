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


def fcurve_points(frames, values):
    """Flat [f0, v0, f1, v1, ...] float32 for FCurve.keyframe_points.foreach_set('co', ...)."""
    co = np.empty((len(frames), 2), np.float32)
    co[:, 0] = frames
    co[:, 1] = values
    return co.ravel()
