"""Viewport test with the real UI under Xvfb: comparing worlds at a glance.

Run by `tests/viewport/run.sh test_browsing.py` (the fixture of test_paths_drawn: a ground and
three boxes, 24 sampled worlds; the test adds a scene camera looking at them). Checks, as a user
would see them:
- the ranking's rows get thumbnails, made after the list is drawn (drawing only asks for them),
  a few per timer tick; thumbnails of two worlds whose last frames differ differ, and a world's
  filmstrip runs from its start (boxes in the air) to its end;
- the sidebar shows the thumbnails, the filmstrip of the selected world and the legend's colour
  swatches (full-window screenshots of each state are kept);
- Alt+Down / Alt+Up over the viewport, while the timeline plays, preview the next / previous world
  of the ranking (Blender 4.3 under Xvfb drops simulated key presses: there the operators bound
  to the keys are run instead).
What one thumbnail costs (mean over those made) is written to result.json.
Exit code 0 = pass.
"""
import json
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds import posing, scene_boxes  # noqa: E402
from many_worlds.core import contact_sheet, palette  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.thumbnails import THUMBNAILS  # noqa: E402
from many_worlds.ui import filmstrip  # noqa: E402
from viewport_helpers import add_camera, colour_mask, no_tooltips, run_steps, viewport  # noqa: E402
import viewport_helpers  # noqa: E402

OUT_DIR = sys.argv[sys.argv.index("--") + 1]
TICK_S = 0.3
RESULTS = {}


def region_pixels(area, region_type):
    """RGB float pixels of one region of the area as drawn (rows bottom first)."""
    region = next(r for r in area.regions if r.type == region_type)
    captured = {}

    def capture():
        if bpy.context.region != region:
            return
        import gpu
        fb = gpu.state.active_framebuffer_get()
        data = fb.read_color(0, 0, region.width, region.height, 4, 0, "FLOAT")
        data.dimensions = region.width * region.height * 4
        captured["rgba"] = np.array(data, dtype=np.float32).reshape(region.height, region.width, 4)

    handle = bpy.types.SpaceView3D.draw_handler_add(capture, (), region_type, "POST_PIXEL")
    try:
        window = bpy.context.window_manager.windows[0]
        area.tag_redraw()
        with bpy.context.temp_override(window=window):
            bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=1)
    finally:
        bpy.types.SpaceView3D.draw_handler_remove(handle, region_type)
    return captured["rgba"][..., :3]


def save_rgb(name, rgb):
    """Keep an RGB float image (rows bottom first) as a PNG in the output folder."""
    contact_sheet.save_png(np.round(np.clip(rgb[::-1, :, :3], 0, 1) * 255).astype(np.uint8),
                           os.path.join(OUT_DIR, name))


def window_screenshot(name):
    viewport_helpers.window_screenshot(OUT_DIR, name)


def show_many_worlds_tab(window, area):
    """The sidebar on the Many Worlds tab: set directly on Blender 4; on 3.4 Ctrl+Wheel over the
    sidebar steps through the tabs as a user would, until the ranking's rows are drawn."""
    area.spaces.active.show_region_ui = True
    area.tag_redraw()
    yield
    sidebar = next(r for r in area.regions if r.type == "UI")
    if hasattr(sidebar, "active_panel_category"):
        sidebar.active_panel_category = "Many Worlds"
    # Over the first panel: with region overlap, the sidebar below its panels is the viewport's.
    x, y = sidebar.x + sidebar.width // 2, sidebar.y + sidebar.height - 40
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    for _ in range(8):
        requested = THUMBNAILS.pending() + THUMBNAILS.made
        region_pixels(area, "UI")
        if THUMBNAILS.pending() + THUMBNAILS.made > requested or THUMBNAILS.made:
            return sidebar
        window.event_simulate(type="WHEELDOWNMOUSE", value="PRESS", x=x, y=y, ctrl=True)
        yield
    window_screenshot("no_ranking.png")
    raise AssertionError("the sidebar never showed the ranking")


def redraw_seconds(area):
    """Seconds to draw the window once (the sidebar's list included), as the fastest of three."""
    times = []
    for _ in range(3):
        begin = time.perf_counter()
        region_pixels(area, "UI")
        times.append(time.perf_counter() - begin)
    return min(times)


def wait_for_thumbnails(timeout_s=60):
    deadline = time.monotonic() + timeout_s
    while THUMBNAILS.pending():
        assert time.monotonic() < deadline, "thumbnails were not made"
        yield 0.1


def step_key(key):
    """The add-on's keymap item bound to Alt+`key`."""
    keymap = bpy.context.window_manager.keyconfigs.addon.keymaps["Frames"]
    return next(item for item in keymap.keymap_items if item.type == key and item.alt and item.value == "PRESS")


def last_frame_pixels(world):
    return THUMBNAILS.pixels(world, posing.last_frame(SESSION.view.library, world))


def steps():
    scene = bpy.context.scene
    window, area, region = viewport()
    view = SESSION.view
    assert view is not None, "the library was not reopened on load"
    area.spaces.active.overlay.show_floor = False
    no_tooltips()
    add_camera(scene)
    for ob in bpy.data.objects:
        ob.select_set(False)
    yield
    # --- thumbnails: asked for by drawing the list, made later by the timer ---------------------
    window_screenshot("before_thumbnails.png")
    yield from show_many_worlds_tab(window, area)
    RESULTS["asked_by_first_draw"] = THUMBNAILS.pending() + THUMBNAILS.made
    yield from wait_for_thumbnails()
    ranked = [int(w) for w in scene_boxes.RANKING.get(bpy.context).ids]
    made = THUMBNAILS.made
    RESULTS["thumbnails_made"] = made
    RESULTS["thumbnail_ms"] = round(1000 * THUMBNAILS.seconds / max(1, made), 1)
    # The sidebar a page down, where the ranking's rows (and later the filmstrip) are in view.
    sidebar = next(r for r in area.regions if r.type == "UI")
    with bpy.context.temp_override(window=window, area=area, region=sidebar):
        bpy.ops.view2d.scroll_down(page=True)
    yield
    region_pixels(area, "UI")
    window_screenshot("thumbnails.png")
    # Drawing the list again with every thumbnail made asks for none and makes none; with none
    # made, drawing it only asks for them: it takes about as long.
    cached_s = redraw_seconds(area)
    assert THUMBNAILS.made == made and THUMBNAILS.pending() == 0
    keep = {w: last_frame_pixels(w) for w in ranked if last_frame_pixels(w) is not None}
    THUMBNAILS.clear()
    asking_s = redraw_seconds(area)
    RESULTS["window_draw_ms"] = {"thumbnails_cached": round(1000 * cached_s, 1),
                                 "thumbnails_missing": round(1000 * asking_s, 1)}
    assert THUMBNAILS.made == made and THUMBNAILS.pending() == len(keep), (THUMBNAILS.pending(), len(keep))
    assert asking_s < 1.5 * cached_s + 0.05, RESULTS
    yield from wait_for_thumbnails()
    assert THUMBNAILS.made == made + len(keep)
    shown = [w for w in ranked if last_frame_pixels(w) is not None]
    RESULTS["rows_with_thumbnails"] = len(shown)
    assert 6 <= len(shown) <= 12, ("the visible rows (and only they) get thumbnails", shown)
    pictures = {w: last_frame_pixels(w) for w in shown}
    for w, rgba in pictures.items():
        assert rgba[..., :3].std() > 0.02, f"thumbnail of world {w} is flat"
    # Worlds whose boxes end elsewhere: their thumbnails differ where the boxes lie.
    ends = {w: view.library.positions(w)[:, -1, :] for w in shown}
    a, b = max(((p, q) for p in shown for q in shown if p < q),
               key=lambda pq: np.nanmax(np.abs(ends[pq[0]] - ends[pq[1]])))
    differ = np.abs(pictures[a] - pictures[b])[..., :3].max(axis=-1) > 0.1
    RESULTS["pixels_differing"] = [a, b, int(differ.sum())]
    save_rgb(f"thumbnail_world_{a}.png", pictures[a])
    save_rgb(f"thumbnail_world_{b}.png", pictures[b])
    # The rows' icons: the part of the picture around the boxes, so they differ as much as the
    # boxes' places do (at 32 pixels, the whole picture would show the boxes as a few dots).
    icons = {w: THUMBNAILS.pixels(w, posing.last_frame(view.library, w), icon=True) for w in (a, b)}
    save_rgb(f"icon_world_{a}.png", np.kron(icons[a], np.ones((4, 4, 1))))
    save_rgb(f"icon_world_{b}.png", np.kron(icons[b], np.ones((4, 4, 1))))
    icon_differ = np.abs(icons[a] - icons[b])[..., :3].max(axis=-1) > 0.1
    RESULTS["icon_pixels_differing"] = int(icon_differ.sum())
    assert icon_differ.mean() > differ.mean(), RESULTS
    assert differ.sum() > 20, RESULTS
    # --- the filmstrip of the selected world --------------------------------------------------
    world = ranked[0]
    bpy.ops.mwb.select_world(world=world)
    area.tag_redraw()
    yield
    region_pixels(area, "UI")
    yield from wait_for_thumbnails()
    region_pixels(area, "UI")
    window_screenshot("filmstrip.png")
    frames = posing.filmstrip_frames(view.library.frame_count(world), filmstrip.FRAMES)
    strip = [THUMBNAILS.pixels(world, f) for f in frames]
    assert 4 <= len(frames) <= 6 and all(p is not None for p in strip), frames
    save_rgb(f"filmstrip_world_{world}.png", np.concatenate([p[..., :3] for p in strip], axis=1))
    moved = np.abs(strip[0] - strip[-1])[..., :3].max(axis=-1) > 0.1
    assert moved.sum() > 20, "the filmstrip's first and last pictures should differ"
    # Its button shows it large, in a popup.
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.show_filmstrip("INVOKE_DEFAULT", world=world) == {"RUNNING_MODAL"}
    yield
    window_screenshot("filmstrip_popup.png")
    window.event_simulate(type="ESC", value="PRESS", x=region.x + 10, y=region.y + 10)
    window.event_simulate(type="ESC", value="RELEASE", x=region.x + 10, y=region.y + 10)
    yield
    # --- the legend's swatches in the sidebar -----------------------------------------------------
    found = {}
    for _ in range(6):
        pixels = region_pixels(area, "UI")
        found = {k: int(colour_mask(pixels, palette.PALETTE[k], 0.02).sum()) for k in range(4)}
        if all(found[k] > 30 for k in range(3)):
            break
        # Scroll the sidebar down a page, towards the Paths subpanel (what the mouse wheel runs).
        with bpy.context.temp_override(window=window, area=area, region=sidebar):
            bpy.ops.view2d.scroll_down(page=True)
        yield
    window_screenshot("legend.png")
    save_rgb("sidebar.png", pixels)
    # The list's rows, now in view, show the thumbnails: drawn with none made yet they show
    # hourglasses, and the sidebar changes there once they are made (8 icons of 16 pixels).
    THUMBNAILS.clear()
    waiting = region_pixels(area, "UI")
    assert THUMBNAILS.pending() > 0
    yield from wait_for_thumbnails()
    shown = region_pixels(area, "UI")
    save_rgb("sidebar_waiting.png", waiting)
    RESULTS["sidebar_pixels_changed"] = int((np.abs(shown - waiting).max(axis=-1) > 0.05).sum())
    assert RESULTS["sidebar_pixels_changed"] > 400, RESULTS
    RESULTS["legend_swatch_pixels"] = found
    # A swatch per box (three objects in three colours), none in a colour no object has.
    assert all(found[k] > 30 for k in range(3)) and found[3] < 5, found
    # --- Alt+Down / Alt+Up step through the ranking while the timeline plays ---------------------
    # A simulated key takes the mouse position it is given (not the last one): over the viewport.
    x, y = region.x + region.width // 2, region.y + region.height // 2
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.animation_play()
    yield
    assert bpy.context.screen.is_animation_playing
    seen = [scene.mwb.selected_world]
    keys_arrive = True
    for key in ("DOWN_ARROW", "DOWN_ARROW", "UP_ARROW"):
        if keys_arrive:
            window.event_simulate(type=key, value="PRESS", alt=True, x=x, y=y)
            window.event_simulate(type=key, value="RELEASE", alt=True, x=x, y=y)
            yield
            # Blender 4.3 under Xvfb drops simulated key presses (even a bare Right Arrow does not
            # move the frame): there, run the operator the add-on binds to the key instead.
            keys_arrive = scene.mwb.selected_world != seen[-1]
        if not keys_arrive:
            item = step_key(key)
            with bpy.context.temp_override(window=window, area=area, region=region):
                assert getattr(bpy.ops.mwb, item.idname.split(".")[1])(step=item.properties.step) == {"FINISHED"}
            yield
        seen.append(scene.mwb.selected_world)
    RESULTS["keys_simulated"] = keys_arrive
    assert keys_arrive or bpy.app.version >= (4, 0, 0), "Alt+Down/Up did not step through the ranking"
    playing = bpy.context.screen.is_animation_playing
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.animation_cancel(restore_frame=True)
    RESULTS["stepped"] = seen
    assert seen == [ranked[0], ranked[1], ranked[2], ranked[1]], (seen, ranked[:4])
    assert playing, "stepping stopped the playback"
    with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
        json.dump(RESULTS, f, indent=1)
    print("browsing results:", RESULTS, flush=True)


def guarded():
    try:
        yield from steps()
    finally:
        with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
            json.dump(RESULTS, f, indent=1)


run_steps(guarded, TICK_S)
