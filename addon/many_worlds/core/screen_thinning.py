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

from .screen_pixels import world_to_pixels

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
    """(pixel x, pixel y from the bottom edge, in front of the camera) float32 of points
    (..., 3) at `view`, each shaped (...)."""
    return world_to_pixels(points, view.perspective, (view.width, view.height), dtype=np.float32)


def kept_on_screen(paths, view):
    """bool (..., points): the vertices of paths float32 (..., points, 3) worth drawing at `view`;
    NaN points (absent bodies, past a path's end: only after its last point) are never kept."""
    finite = np.isfinite(paths[..., 0])
    if paths.shape[-2] == 0:
        return finite
    # NaN points project to NaN, which compares unequal to everything: masked by `finite` below.
    x, y, in_front = pixels(paths, view)
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
