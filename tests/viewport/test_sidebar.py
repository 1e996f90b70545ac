"""Viewport test with the real UI under Xvfb: the sidebar reads in workflow order and no label is cut.

Run by `tests/viewport/run.sh test_sidebar.py` (Blender started with --enable-event-simulate, the
fixture of test_paths_drawn: a ground and three boxes, 24 sampled worlds). The sidebar is opened
at its default width on the Many Worlds tab and the Physics properties show the variation panel.
The scene gets a camera, so the ranking's rows show thumbnails and the previewed world its filmstrip.
For each state a new user meets (library just opened with a passive object selected; its path
index still filling; boxes drawn and a world previewed; an object moved during the preview; the collapsed subpanels opened and the
variation ranges as min/max; a click with Draw Box and the Rigid Body World removed, so that the Boxes panel says why no box came of the click and Sample why it is greyed out, with
a box's time window ending before it starts, which the Boxes and Seek panels name), every panel of the add-on is drawn through a recording layout
(tests/viewport/label_fit.py) and every label, field and button text is measured against the
width the panel gives it. The test fails on any text that does not fit, names it, and keeps a
full-window screenshot of each state in the output folder. It also checks the panel order, that
expert settings start collapsed, that the Paths panel says when a drawing budget leaves paths
out, that the panel says which objects a new box tests (and which
selected objects it leaves out), that the Boxes panel counts the worlds indexed while the path
index fills, and that the preview state and an edit during it are said.
Pose parts (Add Pose with Box0 selected: upright; with Box1: never its local +X up for over 0.5 s)
are listed with the boxes, each one's settings fit, the viewport draws each part's cone and its
object's axis on the object (the pixels the overlay changes near each object), and with nothing
selected the greyed-out Add Pose says why.
The sidebar at its top, halfway and at its end is kept as sidebar.png, and the pose parts beside
the last one's settings as pose_parts.png (the README's pictures).
Exit code 0 = pass.
"""
import contextlib
import json
import os
import shutil
import sys
import threading
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.core import library_query, path_budget  # noqa: E402
from many_worlds.operators import browsing  # noqa: E402
from many_worlds.thumbnails import THUMBNAILS  # noqa: E402
from many_worlds.draw import paths as path_overlay  # noqa: E402
from many_worlds.ui import fit, panels  # noqa: E402
import label_fit  # noqa: E402
from sidebar_recording import (OUT_DIR, crop, measure, open_expert_panels, record_panels, redraw_all,  # noqa: E402
                               save_rgb, scroll, show_many_worlds_tab, texts, window_screenshot)
from viewport_helpers import add_camera, no_tooltips, run_steps, viewport  # noqa: E402
from viewport_helpers import screenshot as viewport_screenshot  # noqa: E402
from bpy_extras import view3d_utils  # noqa: E402
from many_worlds.draw import poses as pose_overlay  # noqa: E402

TICK_S = 0.3
# Wheel steps that bring the Physics tab's Rigid Body settings, with the variation subpanel inside
# them, to the top of the Properties editor.
PROPERTIES_SCROLL_STEPS = 6
SIDEBAR_ORDER = ["Sample", "Expert Settings", "Boxes", "Seek", "Worlds & Ranking", "Paths", "Refine", "Bake"]


@contextlib.contextmanager
def held_index_fill():
    """The path index of a library opened inside fills in the background (even a small one) and
    waits before its first step; on leaving, the fill runs to its end."""
    gate = threading.Event()

    class HeldFill(library_query.IndexFill):
        def _step(self):
            while not gate.wait(0.05):
                if self.stopping:
                    return 0
            return super()._step()

    saved = library_query.IndexFill, library_query.FOREGROUND_WORLDS
    library_query.IndexFill, library_query.FOREGROUND_WORLDS = HeldFill, 0
    try:
        yield
    finally:
        library_query.IndexFill, library_query.FOREGROUND_WORLDS = saved
        gate.set()
    deadline = time.monotonic() + 30
    while SESSION.query is not None and SESSION.query.filling:
        assert time.monotonic() < deadline, "the index did not fill"
        time.sleep(0.01)


def thumbnails_made(timeout_s=60):
    """Wait until the thumbnails the ranking asked for are made (a generator), then redraw."""
    deadline = time.monotonic() + timeout_s
    redraw_all()
    while THUMBNAILS.pending():
        assert time.monotonic() < deadline, "thumbnails were not made"
        yield 0.1
        redraw_all()


def pose_pixels(drawn, without, ob, region, radius_px=80):
    """Counts of the pixels the pose overlay changed within `radius_px` of where `ob`'s origin is
    drawn (screenshots of the region with and without it), by what they look like: green or red
    (a positive or a negative cone; tinted where a box's fill is drawn over them), white or yellow
    (the object's axis within its cone or out of it)."""
    x, y = view3d_utils.location_3d_to_region_2d(region, region.data, ob.matrix_world.translation)
    rows, cols = np.ogrid[:drawn.shape[0], :drawn.shape[1]]
    changed = drawn[(((rows - y) ** 2 + (cols - x) ** 2) < radius_px ** 2) & (np.abs(drawn - without).sum(-1) > 0.3)]
    r, g, b = changed.T
    return {"green": int(((g > r + 0.3) & (g > b + 0.3)).sum()), "red": int(((r > g + 0.3) & (r > b + 0.3)).sum()),
            "white": int((changed.min(axis=-1) > 0.85).sum()), "yellow": int(((r > 0.8) & (g > 0.7) & (b < 0.4)).sum())}


def add_pose_for(names, window, area, region):
    """Press Add Pose with the objects named selected; returns the part it added."""
    for ob in bpy.data.objects:
        ob.select_set(ob.name in names)
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.add_pose() == {"FINISHED"}
    return bpy.context.scene.mwb.boxes[-1]


def pose_part_state(results, window, area, region):
    """Add Pose pressed with Box0 and the ground selected (an Upright part), then with Box1 (made a
    negative part: local +X never towards +Z for over 0.5 s), at the previewed world's last frame:
    the Boxes panel lists them with the boxes and shows each one's settings with no text cut, the
    viewport draws each part's cone and its object's axis on the object, and with nothing selected
    the greyed-out Add Pose says why."""
    scene = bpy.context.scene
    upright = add_pose_for(("Box0", "Ground"), window, area, region)
    assert [b.name for b in upright.bodies] == ["Box0"], "the passive ground was posed"
    upright_index = scene.mwb.box_index
    sideways = add_pose_for(("Box1",), window, area, region)
    sideways.pose_mode, sideways.pose_axis, sideways.pose_direction = "AXIS", "POS_X", "POS_Z"
    sideways.negative, sideways.longer_than_s, sideways.within_deg = True, 0.5, 30.0
    frame = scene.frame_current
    scene.frame_set(scene.frame_end)
    for index, state, said in (
            (upright_index, "pose_part", (f"Pose {upright_index + 1} tests Box0",
                                          "Keeps worlds where Box0's local +Z faces up", "Now: Box0")),
            (scene.mwb.box_index, "pose_axis_negative", (f"Pose {scene.mwb.box_index + 1} tests Box1",
                                                         "Rejects worlds where Box1's local +X faces +Z for over "
                                                         f"0.50{fit.NO_BREAK_SPACE}s", "towards", "Longer Than"))):
        scene.mwb.box_index = index
        yield
        redraw_all()
        results.append(measure(state))
        shot = window_screenshot(f"{state}.png")
        boxes_text = " ".join(texts("Boxes"))
        assert all(text in boxes_text for text in said), (said, boxes_text)
    # The parts on their objects beside the last one's settings (the README's picture).
    sidebar = next(r for r in area.regions if r.type == "UI")
    left = region.x + int(region.width * 0.3)
    save_rgb(shot[sidebar.y:sidebar.y + sidebar.height, left:sidebar.x + sidebar.width], "pose_parts.png")
    if os.environ.get("MWB_TEST_ARTIFACTS"):
        shutil.copy(os.path.join(OUT_DIR, "pose_parts.png"), os.path.join(os.environ["MWB_TEST_ARTIFACTS"],
                                                                          "pose_parts.png"))
    drawn = viewport_screenshot(OUT_DIR, "pose_parts_viewport.png")
    pose_overlay.OVERLAY.remove()
    try:
        without = viewport_screenshot(OUT_DIR, "pose_parts_viewport_without.png")
    finally:
        pose_overlay.OVERLAY.add()
    upright_px = pose_pixels(drawn, without, bpy.data.objects["Box0"], region)
    sideways_px = pose_pixels(drawn, without, bpy.data.objects["Box1"], region)
    assert upright_px["green"] > 100 and sideways_px["red"] > 100, (upright_px, sideways_px)
    assert upright_px["white"] + upright_px["yellow"] > 20 and sideways_px["white"] + sideways_px["yellow"] > 20, (
        upright_px, sideways_px)
    # Nothing selected: Add Pose greys out and the panel says why.
    for ob in bpy.data.objects:
        ob.select_set(False)
    yield
    redraw_all()
    results.append(measure("pose_nothing_selected"))
    window_screenshot("pose_nothing_selected.png")
    assert "To add a pose, select objects the simulation moves" in " ".join(texts("Boxes"))
    for ob in bpy.data.objects:
        ob.select_set(ob.name in ("Box0", "Ground"))
    scene.frame_set(frame)
    yield


def steps():
    results = []
    scene = bpy.context.scene
    window, area, region = viewport()
    assert SESSION.view is not None, "the library was not reopened on load"
    assert "DEFAULT_CLOSED" in panels.MWB_PT_sampling_expert.bl_options, "expert settings start open"
    record_panels()
    no_tooltips()
    # A scene camera: the ranking's rows show thumbnails and the previewed world a filmstrip. It is
    # hidden in the viewport, where it would stand in front of the paths.
    add_camera(scene).hide_set(True)
    properties = next(a for a in window.screen.areas if a.type == "PROPERTIES")
    properties.spaces.active.context = "PHYSICS"
    r3d = area.spaces.active.region_3d
    r3d.view_location = (0.6, 0.0, 0.5)
    r3d.view_distance = 4.0
    area.spaces.active.show_region_ui = True
    yield
    yield from show_many_worlds_tab(window, area)
    yield from scroll(window, properties, steps=PROPERTIES_SCROLL_STEPS)
    sidebar = next(r for r in area.regions if r.type == "UI")
    # A passive object in the selection: left out of a new box, and said so before drawing one.
    for ob in bpy.data.objects:
        ob.select_set(ob.name in ("Box0", "Ground"))
    bpy.context.view_layer.objects.active = bpy.data.objects["Box0"]
    yield
    redraw_all()
    results.append(measure("start"))
    window_screenshot("start.png")
    order = [label for label in results[-1]["drawn"] if label in SIDEBAR_ORDER]
    assert order == [label for label in SIDEBAR_ORDER if label in order], order
    assert "Expert Settings" not in results[-1]["drawn"], "expert settings are open by default"
    boxes_text = " ".join(texts("Boxes"))
    assert "A new box tests Box0" in boxes_text and "Ground" in boxes_text, boxes_text
    assert "Many Worlds Variation" in results[-1]["drawn"], results[-1]["drawn"]

    # The library opened again while its path index still fills: the Boxes panel says how far.
    with held_index_fill():
        assert browsing.open_scene_library(scene)
        yield
        redraw_all()
        results.append(measure("index_filling"))
        window_screenshot("index_filling.png")
        boxes_text = " ".join(texts("Boxes"))
        assert f"Indexing 0 of {len(SESSION.view.world_indices)} worlds" in boxes_text, boxes_text

    # Boxes drawn through the viewport, a world previewed from the ranking.
    with bpy.context.temp_override(window=window, area=area, region=region):
        w, h = region.width, region.height
        bpy.ops.mwb.add_box(rect=(0, 0, w * 0.6, h * 0.6))
        bpy.ops.mwb.add_box(rect=(w * 0.5, h * 0.5, w, h), negative=True)
    scene.mwb.boxes[1].use_time_window = True
    scene.mwb.boxes[1].after = "0"
    assert [b.name for b in scene.mwb.boxes[0].bodies] == ["Box0"], "the passive ground was put in a box"
    bpy.ops.mwb.select_world(world=SESSION.view.world_indices[3])
    scene.frame_set(20)
    # A drawing budget too small for every path: the Paths panel says a subset is shown.
    path_overlay.OVERLAY.vertex_budget = 1000
    yield
    yield from thumbnails_made()
    results.append(measure("boxes_and_preview"))
    paths_text = " ".join(texts("Paths"))
    assert "(drawing budget)" in paths_text, paths_text
    shot = window_screenshot("boxes_and_preview.png")
    # The sidebar alone, at its top, scrolled halfway and to its end, side by side (the README's picture).
    top = crop(shot, "sidebar_top.png", sidebar)
    yield from scroll(window, area, "UI", steps=19)
    redraw_all()
    middle = crop(window_screenshot("boxes_and_preview_ranking.png"), "sidebar_middle.png", sidebar)
    yield from scroll(window, area, "UI")
    redraw_all()
    bottom = crop(window_screenshot("boxes_and_preview_end.png"), "sidebar_bottom.png", sidebar)
    save_rgb(np.concatenate([top, middle, bottom], axis=1), "sidebar.png")
    if os.environ.get("MWB_TEST_ARTIFACTS"):
        # The README's picture, written again: MWB_TEST_ARTIFACTS=tests/viewport.
        shutil.copy(os.path.join(OUT_DIR, "sidebar.png"), os.path.join(os.environ["MWB_TEST_ARTIFACTS"], "sidebar.png"))
    path_overlay.OVERLAY.vertex_budget = path_budget.VERTEX_BUDGET
    # Text is drawn, light on the panels' grey, and the scrolled half shows other panels.
    assert (top.min(axis=-1) > 0.75).sum() > 2000 and (bottom.min(axis=-1) > 0.75).sum() > 2000
    assert np.abs(top - bottom).mean() > 0.02, "the sidebar did not scroll"
    yield from scroll(window, area, "UI", down=False)
    worlds_text = " ".join(texts("Worlds & Ranking"))
    assert f"Previewing world {scene.mwb.selected_world}" in worlds_text, worlds_text
    assert "Of Box0" in worlds_text, "the ranking does not default to the boxes' objects"

    # Pose parts, at the previewed world's last frame: listed with the boxes, drawn on their objects.
    yield from pose_part_state(results, window, area, region)

    # An edit during the preview: asked to end it, not reverted behind the user's back.
    moved = bpy.data.objects["Box1"]
    moved.location.x += 0.5
    bpy.context.view_layer.update()
    yield
    redraw_all()
    results.append(measure("edit_during_preview"))
    window_screenshot("edit_during_preview.png")
    # The question also pops up where the mouse is (a screenshot for the record).
    yield
    redraw_all()
    window_screenshot("edit_during_preview_asked.png")
    worlds_text = " ".join(texts("Worlds & Ranking"))
    assert "Box1 moved" in worlds_text and "End Preview" in worlds_text, worlds_text
    position = moved.matrix_world.translation.x
    scene.frame_set(25)
    assert abs(moved.matrix_world.translation.x - position) < 1e-6, "the moved object was posed again"
    bpy.ops.mwb.end_preview()
    # The preview ended from the panel: its question goes away as the mouse leaves it (or on Esc).
    x, y = region.x + 40, region.y + region.height // 2
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    window.event_simulate(type="ESC", value="PRESS", x=x, y=y)
    window.event_simulate(type="ESC", value="RELEASE", x=x, y=y)
    yield

    # The collapsed subpanels opened, the variation ranges as min and max.
    open_expert_panels()
    bpy.data.objects["Box0"].mwb_variation.show_min_max = True
    yield
    yield from scroll(window, properties, steps=PROPERTIES_SCROLL_STEPS)
    redraw_all()
    results.append(measure("expert_open"))
    window_screenshot("expert_open.png")
    assert "Expert Settings" in results[-1]["drawn"], results[-1]["drawn"]

    # A click with Draw Box (no drag), then the Rigid Body World removed: the Boxes panel says why
    # no box came of it, Sample greys out and its panel says why, all fitting the sidebar.
    x, y = region.x + region.width // 2, region.y + region.height // 2
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    yield
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.draw_box("INVOKE_DEFAULT") == {"RUNNING_MODAL"}
    window.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
    yield
    window.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
    yield
    scene.mwb.box_index = 0
    with bpy.context.temp_override(window=window, area=area, region=region, scene=scene):
        bpy.ops.rigidbody.world_remove()
    # Box 2's time window set to end before it starts: passed on as set, the panel names the box.
    scene.mwb.boxes[1].time_start_s, scene.mwb.boxes[1].time_end_s = 2.0, 1.0
    yield
    yield from scroll(window, area, "UI", down=False)
    redraw_all()
    results.append(measure("no_rigid_body_world"))
    window_screenshot("no_rigid_body_world.png")
    sample_text = " ".join(texts("Sample"))
    assert "Add a Rigid Body World first" in sample_text and "Save the .blend" not in sample_text, sample_text
    boxes_text = " ".join(texts("Boxes"))
    assert "The box was too small (0×0 px)" in boxes_text, boxes_text
    # Box 1 has no time window: the panel says what that means.
    assert "a path that only passes through counts too" in boxes_text, boxes_text
    refused = "Box 2 has a time window (time_window) that ends before it starts"
    assert refused in boxes_text and refused in " ".join(texts("Seek")), boxes_text

    scale = bpy.context.preferences.view.ui_scale
    report = {"blender": bpy.app.version_string, "ui_scale": scale, "sidebar_width": sidebar.width,
              "panel_width": label_fit.panel_width(sidebar, scale, True), "states": results}
    with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
        json.dump(report, f, indent=1)
    for result in results:
        print(f"{result['state']}: tightest {result['tightest']}; cut: {result['cut']}")
    cut = [(r["state"], *c) for r in results for c in r["cut"]]
    assert not cut, f"text cut at the default sidebar width (state, panel, text, needed px, has px): {cut}"


run_steps(steps, TICK_S)
