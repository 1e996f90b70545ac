"""Viewport test with the real UI under Xvfb: Seek on the quick-start example.

Run by `tests/viewport/run.sh test_seek.py`, which opens a fresh copy of
blend_examples/quickstart/quickstart.blend. As a user would: Sample makes a first batch of 8
worlds; the viewport looks through the scene camera at the last frame, and three boxes are drawn
in it over the camera's frame (the marble in the left bin, the cone in the middle one, the pill in
the right one, in the last second: tests/shared/quickstart_goal.py), which no first world meets
together; Ranking is set to Goal Parts Met, best first. Seek is pressed as its button presses it, with
Find 1 and the default budget. While it runs, the panel's line "best N of 3 parts (world W), K
worlds made" never goes down and world W is the world selected; it ends with "Goal reached: 1
world meets all 3 parts" and the selected, previewed world meets all three by the add-on's own
query. A second seek (Find 1000, a large budget) is stopped with Esc: every world made stays.
Full-window screenshots (seeking, ended, cancelled) show the sidebar's Many Worlds tab at its
default width with the Query Boxes panel. Exit code 0 = pass.
"""
import json
import os
import re
import sys
import time

import bpy
from bpy_extras.view3d_utils import location_3d_to_region_2d

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "shared"))

from many_worlds import _native, scene_boxes  # noqa: E402
from many_worlds.core import engine as engine_process  # noqa: E402
from many_worlds.core.library_query import BOXES_MET  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from quickstart_goal import GOAL, add_goal_boxes  # noqa: E402
from viewport_helpers import run_steps, viewport  # noqa: E402

OUT_DIR = sys.argv[sys.argv.index("--") + 1]
TICK_S = 0.15
FIRST_WORLDS = 8
THREADS = 2
# Below the sidebar's top: its first panel header, a folded panel's height, and the Many Worlds
# tab (after Item, Tool, View); factory settings, UI scale 1.
HEADER_BELOW_TOP_PX = 15
FOLDED_PANEL_PX = 28
TAB_BELOW_TOP_PX = 182
SEEKING = re.compile(r"Seeking: best (\d+) of 3 parts \(world (\d+)\), ([\d,]+) worlds made")


def simulate(window, kind, value, x, y):
    window.event_simulate(type=kind, value=value, x=int(x), y=int(y))


def click(window, x, y):
    simulate(window, "MOUSEMOVE", "NOTHING", x, y)
    yield
    simulate(window, "LEFTMOUSE", "PRESS", x, y)
    yield
    simulate(window, "LEFTMOUSE", "RELEASE", x, y)
    yield


def show_query_panel(window, area):
    """The sidebar on the Many Worlds tab, with Sample folded so the Boxes panel and its Seek
    subpanel are at the top (clicks, as a user would; Blender 3.4 has no Python for either)."""
    area.spaces.active.show_region_ui = True
    area.tag_redraw()
    yield
    ui = next(r for r in area.regions if r.type == "UI")
    top = ui.y + ui.height
    yield from click(window, ui.x + ui.width - 14, top - TAB_BELOW_TOP_PX)
    yield from click(window, ui.x + 60, top - HEADER_BELOW_TOP_PX)


def screenshot(window, area, region, name):
    """The whole window, sidebar included."""
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.screenshot(filepath=os.path.join(OUT_DIR, name))


def camera_frame_px(region):
    """The scene camera's frame (x0, y0, x1, y1) in the pixels of a region that looks through it."""
    scene = bpy.context.scene
    corners = [scene.camera.matrix_world @ v for v in scene.camera.data.view_frame(scene=scene)]
    xs, ys = zip(*(location_3d_to_region_2d(region, region.data, c) for c in corners))
    return min(xs), min(ys), max(xs), max(ys)


def boxes_met(world):
    """The boxes a world meets, as the add-on's query (Ranking's Goal Parts Met) counts them."""
    return int(scene_boxes.library_query().result.boxes_satisfied[SESSION.view.world_indices.index(world)])


def press(window, area, region, operator):
    """Press a button that starts an engine run: invoked, it stays modal until the run ends."""
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert operator("INVOKE_DEFAULT") == {"RUNNING_MODAL"}, SESSION.status


def steps():
    results = {}
    window, area, region = viewport()
    settings = bpy.context.scene.mwb
    assert SESSION.view is None, "a fresh copy of the example has no library yet"

    # A first batch of worlds, as the Sample button starts it.
    settings.world_count, settings.threads = FIRST_WORLDS, THREADS
    started = time.monotonic()
    press(window, area, region, bpy.ops.mwb.sample)
    while SESSION.run is not None:
        yield
    assert SESSION.last_error == "", SESSION.last_error
    assert len(SESSION.view.world_indices) == FIRST_WORLDS, SESSION.view.world_indices
    results["sample_s"] = round(time.monotonic() - started, 1)
    yield from show_query_panel(window, area)

    # Through the scene camera, its frame filling the viewport, at the run's end (where the boxes
    # are met); Ranking by Goal Parts Met, descending, lists every world with the best first.
    area.spaces.active.region_3d.view_perspective = "CAMERA"
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.view3d.view_center_camera()
    bpy.context.scene.frame_set(bpy.context.scene.frame_end)
    settings.rank_metric, settings.rank_descending = BOXES_MET, True
    yield
    with bpy.context.temp_override(window=window, area=area, region=region):
        boxes = add_goal_boxes(camera_frame_px(region))
    assert [box.bodies[0].name for box in boxes] == [body for body, _ in GOAL]
    first = list(SESSION.view.world_indices)
    first_met = max(boxes_met(w) for w in first)
    assert first_met < 3, "no world of the first batch should meet the whole goal yet"

    # Seek with Find 1 and the panel's default budget.
    assert settings.seek_want == 1 and settings.seek_budget_worlds == 2000 and settings.seek_budget_s == 0
    started = time.monotonic()
    press(window, area, region, bpy.ops.mwb.seek)
    run = SESSION.run
    assert run is not None and SESSION.runs[-1].label == "Seeking"
    # (boxes met by the best world, the best world, the selected world) as the panel shows them,
    # and each line it showed with the seconds since Seek was pressed.
    shown, lines, shot = [], [], False
    while SESSION.run is not None:
        yield
        lines.append((round(time.monotonic() - started, 1), SESSION.status))
        said = SEEKING.match(SESSION.status)
        if said:
            shown.append((int(said[1]), int(said[2]), settings.selected_world))
            if not shot and len(SESSION.view.world_indices) > len(first):
                screenshot(window, area, region, "seeking.png")
                shot = True
    seek_s = time.monotonic() - started
    assert SESSION.last_error == "", SESSION.last_error
    outcome = engine_process.SeekOutcome.from_summary(run.summary())
    made = len(SESSION.view.world_indices) - len(first)
    assert outcome is not None and made == outcome.worlds_made > 0, (run.summary(), made)
    assert [item.world_index for item in settings.worlds] == SESSION.view.world_indices
    # The panel named a best world while it ran, always the one selected; the boxes it meets never
    # went down and ended higher than the first batch's best.
    assert shown and all(best == selected for _, best, selected in shown), shown
    met = [first_met] + [m for m, _, _ in shown] + [outcome.best_boxes_met]
    assert met == sorted(met) and met[-1] > first_met, met
    # The goal is reached, and the world selected and previewed meets every box.
    # One refinement makes several worlds at once: more than the one wanted may meet the goal.
    assert outcome.reached and outcome.best_boxes_met == 3 and outcome.best in outcome.found, outcome
    assert all(boxes_met(w) == 3 for w in outcome.found), outcome
    assert SESSION.status == outcome.text and f"({outcome.found[0]}" in SESSION.status, SESSION.status
    assert settings.selected_world == outcome.best and settings.previewing, (settings.selected_world, outcome)
    assert settings.worlds[settings.world_list_index].world_index == outcome.best
    assert boxes_met(settings.selected_world) == 3
    assert SESSION.view.matching[SESSION.view.world_indices.index(settings.selected_world)]
    yield
    screenshot(window, area, region, "seek_ended.png")
    results.update(first_met=first_met, shown=shown, lines=lines, outcome=outcome.__dict__, status=SESSION.status,
                   seek_s=round(seek_s, 1))

    # A long seek stopped with Esc keeps every world it made.
    before = len(SESSION.view.world_indices)
    settings.seek_want, settings.seek_budget_worlds = 1000, 100000
    started = time.monotonic()
    press(window, area, region, bpy.ops.mwb.seek)
    while SESSION.run is not None and len(SESSION.view.world_indices) < before + 16:
        yield
    simulate(window, "MOUSEMOVE", "NOTHING", region.x + 300, region.y + 300)
    yield
    simulate(window, "ESC", "PRESS", region.x + 300, region.y + 300)
    yield
    simulate(window, "ESC", "RELEASE", region.x + 300, region.y + 300)
    while SESSION.run is not None:
        yield
    stored = len(_native.Library(SESSION.view.path).world_indices)
    assert SESSION.status.startswith("Seek cancelled: best"), SESSION.status
    assert f"the library keeps {stored:,} worlds" in SESSION.status, SESSION.status
    assert before + 16 <= stored == len(SESSION.view.world_indices) < before + 100000, stored
    yield
    screenshot(window, area, region, "seek_cancelled.png")
    results.update(cancelled_status=SESSION.status, cancel_s=round(time.monotonic() - started, 1))
    with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
        json.dump(results, f, indent=1)
    print("seek results:", results)


run_steps(steps, TICK_S)
