"""Thumbnails of worlds for the ranking: the scene seen from its camera with a world's objects
posed at one recorded frame, drawn on the GPU (an offscreen draw of the 3D view) and kept as
preview icons.

Drawing a row only asks for its thumbnail: the ones missing are made later by a timer, a few
per tick within a time budget, so the list never waits for them. They are kept per world and
frame until the library, the scene camera (where it is, its lens) or the render size changes.
A scene without a camera has no thumbnails.
"""
import time

import bpy
import bpy.utils.previews
import gpu
import numpy as np

from . import posing
from .core.screen_pixels import world_to_pixels
from .core.session import SESSION

IMAGE_WIDTH = 160      # pixels; the height follows the render's aspect
ICON_PIXELS = 32       # the square icon a list row shows: the part of the image around the objects
BUDGET_S = 0.05        # drawing time one timer tick may spend (at least one thumbnail a tick)
TICK_S = 0.02


def camera_signature(scene):
    """What a thumbnail depends on besides the world, or None without a scene camera."""
    camera = scene.camera
    if camera is None or camera.type != "CAMERA":
        return None
    data = camera.data
    render = scene.render
    return (scene.name, camera.name, tuple(round(v, 5) for row in camera.matrix_world for v in row),
            data.type, round(data.lens, 4), round(data.ortho_scale, 4), round(data.sensor_width, 4),
            data.sensor_fit, round(data.shift_x, 4), round(data.shift_y, 4),
            render.resolution_x, render.resolution_y, render.pixel_aspect_x, render.pixel_aspect_y)


def image_size(scene):
    render = scene.render
    aspect = (render.resolution_y * render.pixel_aspect_y) / max(1e-6, render.resolution_x * render.pixel_aspect_x)
    return IMAGE_WIDTH, max(8, int(round(IMAGE_WIDTH * aspect)))


def icon_pixels(rgba, square=None):
    """A square of an image (height, width, 4) resampled to ICON_PIXELS: `square` (left, bottom,
    side) in pixels, rows bottom first, or the middle of the image."""
    height, width = rgba.shape[:2]
    if square is None:
        side = min(height, width)
        square = ((width - side) // 2, (height - side) // 2, side)
    left, bottom, side = square
    index = (np.arange(ICON_PIXELS) * side / ICON_PIXELS).astype(int)
    return rgba[bottom + index][:, left + index]


def focus_square(points, view_matrix, projection, size):
    """(left, bottom, side): the square of the image around the world points (n, 3) the camera
    sees, with a margin, or None when it sees none. A row's icon is this square, so the objects,
    which are what differs between worlds, fill the few pixels it has."""
    width, height = size
    x, y, visible = world_to_pixels(points, np.asarray(projection) @ np.asarray(view_matrix), size)
    inside = visible & (x >= 0) & (x < width) & (y >= 0) & (y < height)
    if not inside.any():
        return None
    x, y = x[inside], y[inside]
    limit = min(width, height)
    # Origins only are known: the margin leaves room for the objects around them.
    side = int(min(limit, max(limit // 3, max(np.ptp(x), np.ptp(y)) + limit // 4)))
    left = int(np.clip((x.min() + x.max() - side) / 2, 0, width - side))
    bottom = int(np.clip((y.min() + y.max() - side) / 2, 0, height - side))
    return left, bottom, side


def view_3d():
    """(window, space, region) of a 3D view to draw with, or None when no window shows one."""
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else []):
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                region = next((r for r in area.regions if r.type == "WINDOW"), None)
                if region is not None:
                    return window, area.spaces.active, region
    return None


def draw_posed(scene, view_layer, space, region, world, frame, size):
    """(RGBA float (height, width, 4) rows bottom first, view matrix, projection matrix): the
    scene from its camera with `world`
    posed at recorded `frame`, drawn as the 3D view's shading draws it (solid when the view
    renders with a render engine, which would be too slow for a list), without overlays."""
    width, height = size
    camera = scene.camera
    offscreen = gpu.types.GPUOffScreen(width, height)
    overlays, shading = space.overlay.show_overlays, space.shading.type
    space.overlay.show_overlays = False
    if shading == "RENDERED":
        space.shading.type = "SOLID"
    try:
        with posing.posed(scene, view_layer, SESSION.view, world, frame):
            projection = camera.calc_matrix_camera(view_layer.depsgraph, x=width, y=height,
                                                   scale_x=scene.render.pixel_aspect_x,
                                                   scale_y=scene.render.pixel_aspect_y)
            view_matrix = camera.matrix_world.inverted()
            offscreen.draw_view3d(scene, view_layer, space, region, view_matrix, projection,
                                  do_color_management=True)
            with offscreen.bind():
                buffer = gpu.state.active_framebuffer_get().read_color(0, 0, width, height, 4, 0, "FLOAT")
    finally:
        space.overlay.show_overlays = overlays
        space.shading.type = shading
        offscreen.free()
    buffer.dimensions = width * height * 4
    rgba = np.array(buffer, dtype=np.float32).reshape(height, width, 4)
    rgba[..., 3] = 1.0
    return rgba, np.array(view_matrix), np.array(projection)


class ThumbnailCache:
    """Preview icons of (world, recorded frame), made lazily by a timer."""

    def __init__(self):
        self._previews = None
        self._signature = None
        self._wanted = {}          # key -> (world, frame), oldest request first
        self._timer_running = False
        self.made = 0              # thumbnails made since the add-on was registered
        self.seconds = 0.0         # time spent making them (posing, drawing, reading back)
        self._tick_function = self._tick   # one bound method, so the timer can be found again
        self._failed = False       # a draw failed: ask for no more until the cache is emptied

    @staticmethod
    def key(world, frame):
        return f"{world}:{frame}"

    def _valid(self, scene):
        """The cache for this library and camera (emptied when either changed); False without them."""
        view = SESSION.view
        signature = camera_signature(scene)
        if view is None or signature is None:
            return False
        signature = (id(view), view.path) + signature
        if signature != self._signature:
            self.clear()
            self._signature = signature
        return True

    def icon(self, scene, world, frame=None):
        """icon_id of the thumbnail of `world` at recorded `frame` (default: its last frame), or 0
        while it is being made (then it is asked for) or when there can be none."""
        if self._failed or not self._valid(scene) or world not in SESSION.view.world_indices:
            return 0
        if frame is None:
            frame = posing.last_frame(SESSION.view.library, world)
        key = self.key(world, frame)
        if self._previews is not None and key in self._previews:
            return self._previews[key].icon_id
        self._wanted[key] = (world, frame)
        if not self._timer_running:
            self._timer_running = True
            bpy.app.timers.register(self._tick_function, first_interval=TICK_S)
        return 0

    def pixels(self, world, frame, icon=False):
        """The made image (or with `icon`, the row's icon) as RGBA float (height, width, 4), or None."""
        key = self.key(world, frame)
        if self._previews is None or key not in self._previews:
            return None
        preview = self._previews[key]
        width, height = preview.icon_size if icon else preview.image_size
        values = preview.icon_pixels_float if icon else preview.image_pixels_float
        return np.array(values[:], dtype=np.float32).reshape(height, width, 4)

    def pending(self):
        return len(self._wanted)

    def _tick(self):
        try:
            return self._make_some()
        except Exception:
            # Said once (the traceback is printed); the list goes on without thumbnails.
            self._failed = True
            self._wanted.clear()
            self._timer_running = False
            raise

    def _make_some(self):
        target = view_3d()
        scene = bpy.context.scene
        if target is None or not self._valid(scene):
            self._wanted.clear()
        start = time.perf_counter()
        while self._wanted and (time.perf_counter() - start < BUDGET_S):
            key, (world, frame) = next(iter(self._wanted.items()))
            del self._wanted[key]
            if world in SESSION.view.world_indices:
                self._make(scene, target, key, world, frame)
        wm = bpy.context.window_manager
        for window in (wm.windows if wm else []):
            for area in window.screen.areas:
                if area.type == "VIEW_3D":
                    area.tag_redraw()
        if self._wanted:
            return TICK_S
        self._timer_running = False
        return None

    def _make(self, scene, target, key, world, frame):
        window, space, region = target
        size = image_size(scene)
        began = time.perf_counter()
        rgba, view_matrix, projection = draw_posed(scene, window.view_layer, space, region, world, frame, size)
        view = SESSION.view
        pose = posing.world_pose(view.library, world, frame, view.simulated_bodies())
        square = focus_square([location for location, _ in pose.values()], view_matrix, projection, size)
        if self._previews is None:
            self._previews = bpy.utils.previews.new()
        preview = self._previews.new(key)
        preview.image_size = size
        preview.image_pixels_float = rgba.ravel().tolist()
        preview.icon_size = (ICON_PIXELS, ICON_PIXELS)
        preview.icon_pixels_float = icon_pixels(rgba, square).ravel().tolist()
        self.seconds += time.perf_counter() - began
        self.made += 1

    def clear(self):
        self._wanted.clear()
        if self._previews is not None:
            bpy.utils.previews.remove(self._previews)
            self._previews = None
        self._signature = None
        self._failed = False

    def unregister(self):
        self.clear()
        if bpy.app.timers.is_registered(self._tick_function):
            bpy.app.timers.unregister(self._tick_function)
        self._timer_running = False


THUMBNAILS = ThumbnailCache()
