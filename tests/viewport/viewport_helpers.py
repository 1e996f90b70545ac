"""Helpers shared by the viewport tests: finding the 3D viewport, screenshots of it as numpy
arrays, colour masks, and a timer-driven runner (one generator step per tick, exit code out)."""
import os
import sys
import traceback

import bpy
import gpu
import numpy as np
from mathutils import Vector


def colour_mask(rgb, colour, tolerance=0.12):
    """Pixels within `tolerance` (per channel, display space) of an opaque overlay colour."""
    return np.all(np.abs(rgb - np.array(colour[:3])) < tolerance, axis=-1)


def viewport():
    """(window, area, region) of the largest 3D viewport."""
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region


def add_camera(scene):
    """A scene camera looking down at the fixture's boxes from the front right (the ranking's
    thumbnails and filmstrips are seen through it)."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    camera.location = (2.0, -2.4, 1.7)
    camera.rotation_euler = (Vector((0.6, 0.0, 0.5)) - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y = 1280, 720
    return camera


def no_tooltips():
    """No tooltips: the mouse left over a button would cover part of a screenshot with one."""
    bpy.context.preferences.view.show_tooltips = False


def screenshot(out_dir, name):
    """The 3D viewport region's RGB pixels as drawn (overlays included), also saved as out_dir/name.

    Read back from the region's framebuffer at the end of a forced redraw: Blender 4.3's screenshot
    operator returns black under Xvfb with Mesa's llvmpipe, while the framebuffer holds the image.
    """
    window, area, region = viewport()
    captured = {}

    def capture():
        if bpy.context.region != region:
            return
        buffer = gpu.state.active_framebuffer_get().read_color(0, 0, region.width, region.height, 4, 0, "FLOAT")
        buffer.dimensions = region.width * region.height * 4
        captured["rgba"] = np.array(buffer, dtype=np.float32).reshape(region.height, region.width, 4)

    # Added last, so it runs after every other overlay of the region.
    handle = bpy.types.SpaceView3D.draw_handler_add(capture, (), "WINDOW", "POST_PIXEL")
    try:
        with bpy.context.temp_override(window=window, area=area, region=region):
            bpy.ops.wm.redraw_timer(type="DRAW", iterations=1)
    finally:
        bpy.types.SpaceView3D.draw_handler_remove(handle, "WINDOW")
    rgba = captured["rgba"]
    image = bpy.data.images.new(name, region.width, region.height)
    image.pixels.foreach_set(np.clip(rgba, 0, 1).ravel())
    image.filepath_raw = os.path.join(out_dir, name)
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
    # Framebuffer rows start at the bottom-left, like region coordinates.
    return rgba[..., :3]


def redraw_window(window):
    """Draw every area of the window now."""
    for area in window.screen.areas:
        area.tag_redraw()
    with bpy.context.temp_override(window=window):
        bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=1)


def window_region_pixels(window, redraw):
    """[(region, RGB)] of every region of the window, read back from its framebuffer during one
    redraw (`redraw()`; each space's draw handlers run in their own regions)."""
    captured, handles = [], []
    for area in window.screen.areas:
        space_type = type(area.spaces.active)
        for region in area.regions:
            if region.width < 2 or region.height < 2:
                continue

            def capture(region=region):
                if bpy.context.region != region:
                    return
                buffer = gpu.state.active_framebuffer_get().read_color(
                    0, 0, region.width, region.height, 4, 0, "FLOAT")
                buffer.dimensions = region.width * region.height * 4
                rgba = np.array(buffer, dtype=np.float32).reshape(region.height, region.width, 4)
                captured.append((region, rgba[..., :3]))
            try:
                handle = space_type.draw_handler_add(capture, (), region.type, "POST_PIXEL")
            except (TypeError, ValueError, AttributeError):
                continue
            handles.append((space_type, handle, region.type))
    try:
        redraw()
    finally:
        for space_type, handle, region_type in handles:
            space_type.draw_handler_remove(handle, region_type)
    return captured


def window_screenshot(out_dir, name, redraw=None):
    """The whole window as the user sees it (saved as out_dir/name), as RGB rows from the bottom.

    Blender 4's screenshot operator saves black under Xvfb's software GL; the window is then put
    together from its regions' framebuffers, read during `redraw()` (default: a redraw of the
    window; main regions first, the overlapping sidebar and toolbar over them).
    """
    window = bpy.context.window_manager.windows[0]
    path = os.path.join(out_dir, name)
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.screen.screenshot(filepath=path, check_existing=False)
    image = bpy.data.images.load(path)
    width, height = image.size
    rgb = np.array(image.pixels[:], dtype=np.float32).reshape(height, width, 4)[..., :3]
    bpy.data.images.remove(image)
    if rgb.max() > 0.05:
        return rgb
    rgb = np.zeros((window.height, window.width, 3), np.float32)
    regions = window_region_pixels(window, redraw or (lambda: redraw_window(window)))
    for region, pixels in sorted(regions, key=lambda rp: rp[0].type in ("UI", "TOOLS")):
        x, y = region.x - window.x, region.y - window.y
        h, w = pixels.shape[:2]
        rgb[y:y + h, x:x + w] = pixels[:max(0, rgb.shape[0] - y), :max(0, rgb.shape[1] - x)]
    save_rgb(rgb, path)
    return rgb


def save_rgb(rgb, path):
    """Save RGB float pixels (rows from the bottom) as a PNG."""
    name = os.path.basename(path)
    image = bpy.data.images.new(name, rgb.shape[1], rgb.shape[0])
    image.pixels.foreach_set(np.concatenate([rgb, np.ones(rgb.shape[:2] + (1,), np.float32)], axis=-1).ravel())
    image.filepath_raw = path
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)


def run_steps(steps, tick_s):
    """Run a generator one step per timer tick; exit Blender with 0 when it ends, 1 on an error."""
    runner = steps()

    def tick():
        try:
            delay = next(runner)
            return tick_s if delay is None else delay
        except StopIteration:
            code = 0
        except Exception:
            traceback.print_exc()
            code = 1
        sys.stdout.flush()
        os._exit(code)

    bpy.app.timers.register(tick, first_interval=1.0)
