"""Thinning paths in screen space (bpy-free): a path vertex that projects within about a pixel of
the last one kept adds nothing visible, so it is dropped.

Pixels are grouped into square cells whose diagonal is the tolerance; a vertex is kept when it
lands in another cell than the vertex before it, so every dropped vertex shares its cell with the
last kept one and lies within the tolerance of it. Each path keeps its first and last point, any
sharp turn (the direction reverses by more than 90 degrees between steps of at least half the
tolerance), and every point behind the camera. Kept vertices are never moved.
"""
from dataclasses import dataclass

import numpy as np

# Vertices closer than this on screen to the last kept one are dropped, pixels.
TOLERANCE_PX = 1.0


@dataclass(frozen=True)
class ScreenView:
    """Where paths land on screen: perspective (4, 4) = projection @ view (world to clip, OpenGL
    convention), and the viewport's size in pixels."""
    perspective: tuple
    width: int
    height: int
    tolerance_px: float = TOLERANCE_PX


def pixels(points, view):
    """(pixel xy (..., 2) float32, in front of the camera (...) bool) of points (..., 3)."""
    x, y, in_front = _pixel_coordinates(points, view)
    return np.stack([x, y], axis=-1), in_front


def _pixel_coordinates(points, view):
    """(pixel x, pixel y, in front of the camera) of points (..., 3), each shaped (...)."""
    m = np.asarray(view.perspective, np.float32)
    clip_x = points @ m[0, :3] + m[0, 3]
    clip_y = points @ m[1, :3] + m[1, 3]
    clip_w = points @ m[3, :3] + m[3, 3]
    in_front = clip_w > 1e-6
    w = np.where(in_front, clip_w, np.float32(1))
    return (clip_x / w + 1) * np.float32(0.5 * view.width), (clip_y / w + 1) * np.float32(0.5 * view.height), in_front


def kept_on_screen(paths, view):
    """bool (..., points): the vertices of paths float32 (..., points, 3) worth drawing at `view`;
    NaN points (absent bodies, past a path's end: only after its last point) are never kept."""
    finite = np.isfinite(paths[..., 0])
    if paths.shape[-2] == 0:
        return finite
    # NaN points project to NaN, which compares unequal to everything: masked by `finite` below.
    x, y, in_front = _pixel_coordinates(paths, view)
    cell = np.float32(view.tolerance_px / np.sqrt(2))
    cell_x, cell_y = np.floor(x / cell), np.floor(y / cell)
    keep = ~in_front
    keep[..., 0] = True
    keep[..., 1:] |= (cell_x[..., 1:] != cell_x[..., :-1]) | (cell_y[..., 1:] != cell_y[..., :-1])
    # The last point of each path: finite with no finite point after it.
    keep[..., :-1] |= ~finite[..., 1:]
    keep[..., -1] = True
    step_x, step_y = np.diff(x, axis=-1), np.diff(y, axis=-1)
    long_enough = step_x * step_x + step_y * step_y >= np.float32((0.5 * view.tolerance_px) ** 2)
    reverses = step_x[..., :-1] * step_x[..., 1:] + step_y[..., :-1] * step_y[..., 1:] < 0
    keep[..., 1:-1] |= reverses & long_enough[..., :-1] & long_enough[..., 1:]
    return keep & finite
