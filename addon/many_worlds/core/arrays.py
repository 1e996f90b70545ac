"""Array shaping between the library's numpy arrays and what drawing and baking need."""
import numpy as np


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
