"""Helpers shared by the viewport tests: finding the 3D viewport, screenshots of it as numpy
arrays, colour masks, and a timer-driven runner (one generator step per tick, exit code out)."""
import os
import sys
import traceback

import bpy
import numpy as np


def colour_mask(rgb, colour, tolerance=0.12):
    """Pixels within `tolerance` (per channel, display space) of an opaque overlay colour."""
    return np.all(np.abs(rgb - np.array(colour[:3])) < tolerance, axis=-1)


def viewport():
    """(window, area, region) of the largest 3D viewport."""
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region


def screenshot(out_dir, name):
    """Screenshot of the window saved as out_dir/name; returns the 3D viewport region's RGB pixels."""
    window, area, region = viewport()
    path = os.path.join(out_dir, name)
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.screenshot(filepath=path)
    image = bpy.data.images.load(path)
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    rgb = pixels.reshape(height, width, 4)[..., :3]
    # Blender images start at the bottom-left, like region coordinates within the window.
    return rgb[region.y:region.y + region.height, region.x:region.x + region.width]


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
