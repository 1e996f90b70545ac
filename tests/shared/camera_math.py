"""Camera matrices built by hand for tests: a look-at view and an OpenGL perspective, and where a
world point lands on screen. Independent of Blender, so tests can check queries against it."""
import math

import numpy as np


def look_at(eye, target):
    """World-to-camera matrix of a camera at eye looking at target, Z up (OpenGL convention)."""
    eye, target = np.asarray(eye, float), np.asarray(target, float)
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0, 0, 1])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    view = np.identity(4)
    view[0, :3], view[1, :3], view[2, :3] = right, up, -forward
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def perspective(fov_y, aspect, near, far):
    """Camera-to-clip matrix of a perspective camera (vertical field of view in radians)."""
    c = 1 / math.tan(fov_y / 2)
    return np.array([[c / aspect, 0, 0, 0], [0, c, 0, 0],
                     [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)], [0, 0, -1, 0]])


def screen_of(view, projection, size, point):
    """Pixel coordinates (origin bottom-left) of a world point in a viewport of `size`."""
    clip = projection @ view @ np.append(point, 1.0)
    ndc = clip[:3] / clip[3]
    return (ndc[0] + 1) / 2 * size[0], (ndc[1] + 1) / 2 * size[1]
