"""World points to pixels of a view (bpy-free): the one projection the viewport's path thinning,
the contact sheet and the row icons use."""
import numpy as np

# A point this close to the eye's plane (clip w) or behind it is not in front of the camera.
IN_FRONT_W = 1e-6


def world_to_pixels(points, perspective, size, y_down=False, dtype=np.float64):
    """(pixel x, pixel y, in front of the camera) of world points (..., 3), each shaped (...).

    perspective: (4, 4) world to clip (projection @ view, OpenGL convention); size: (width,
    height) in pixels. y counts up from the bottom edge, as Blender's regions do, or with
    `y_down` down from the top edge, as image rows do. Computed in `dtype`. The pixels of points
    not in front of the camera mean nothing: mask them with the third array.
    """
    m = np.asarray(perspective, dtype)
    points = np.asarray(points, dtype)
    clip_x = points @ m[0, :3] + m[0, 3]
    clip_y = points @ m[1, :3] + m[1, 3]
    clip_w = points @ m[3, :3] + m[3, 3]
    in_front = clip_w > IN_FRONT_W
    w = np.where(in_front, clip_w, dtype(1))
    half_width, half_height = dtype(0.5 * size[0]), dtype(0.5 * size[1])
    y = (1 - clip_y / w) if y_down else (clip_y / w + 1)
    return (clip_x / w + 1) * half_width, y * half_height, in_front
