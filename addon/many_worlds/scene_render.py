"""The scene rendered from its camera by Blender's own renderer, as one world has it: the
pictures behind the command line's contact sheet.

Workbench where Blender can make a GL context (a display, or a virtual one such as Xvfb), Cycles
on the CPU at low samples otherwise. Whether a GL context exists is tried in a child Blender,
because a Blender without one may abort instead of failing.
"""
import os
import subprocess
import tempfile

import bpy
import numpy as np

from . import posing

WORKBENCH = "BLENDER_WORKBENCH"
CYCLES = "CYCLES"
ENGINES = {"workbench": WORKBENCH, "cycles": CYCLES}
CYCLES_SAMPLES = 16
_PROBE = ("import bpy, sys\n"
          "render = bpy.context.scene.render\n"
          "render.engine = 'BLENDER_WORKBENCH'\n"
          "render.resolution_x = render.resolution_y = 8\n"
          "render.filepath = sys.argv[-1]\n"
          "bpy.ops.render.render(write_still=True)\n")


def gl_context_available():
    """True when a child Blender renders a tiny Workbench image (it needs a GL context)."""
    with tempfile.TemporaryDirectory(prefix="mwb-gl-") as folder:
        out = os.path.join(folder, "probe.png")
        command = [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
                   "--python-expr", _PROBE, "--", out]
        try:
            result = subprocess.run(command, capture_output=True, timeout=120)
        except (OSError, subprocess.TimeoutExpired):
            return False
        return result.returncode == 0 and os.path.isfile(out)


def choose_engine(name="auto"):
    """(render engine, why) for `name`: 'workbench', 'cycles' or 'auto'."""
    if name != "auto":
        return ENGINES[name], "as asked"
    if gl_context_available():
        return WORKBENCH, "a GL context exists"
    return CYCLES, f"no GL context here; {CYCLES_SAMPLES} samples on the CPU"


def set_up(scene, engine, width, height):
    """Render settings of a tile: `engine`, `width` x `height` pixels, an opaque PNG."""
    render = scene.render
    render.engine = engine
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    render.film_transparent = False
    render.image_settings.file_format = "PNG"
    render.image_settings.color_mode = "RGB"
    if engine == CYCLES:
        scene.cycles.device = "CPU"
        scene.cycles.samples = CYCLES_SAMPLES
        scene.cycles.use_denoising = False
        if hasattr(scene.cycles, "use_adaptive_sampling"):
            scene.cycles.use_adaptive_sampling = False


def render_image(scene, path):
    """Render the scene's camera to `path`; returns the picture as RGB uint8 (rows top first)."""
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    try:
        width, height = image.size
        pixels = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    rgb = pixels.reshape(height, width, 4)[::-1, :, :3]
    return np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8)


def render_worlds(scene, view, worlds, width, height, engine):
    """The scene rendered at each world's last frame: [RGB uint8 (height, width, 3)] per world."""
    set_up(scene, engine, width, height)
    view_layer = bpy.context.view_layer
    images = []
    with tempfile.TemporaryDirectory(prefix="mwb-render-") as folder:
        for world in worlds:
            with posing.posed(scene, view_layer, view, world, posing.last_frame(view.library, world),
                              hide_render=True):
                images.append(render_image(scene, os.path.join(folder, f"world_{world}.png")))
    return images
