"""Viewport test with the real UI under Xvfb: Seek in the Query Boxes panel.

Run by `tests/viewport/run.sh test_seek.py`. Three boxes are drawn through the viewport's view,
each around where one dropped box ends in a different world, the third to be met after the first
(set in the panel's After menu, as a user would). Seek is pressed as its button presses it: new
worlds stream into the library view, the panel reads "best N of 3 boxes (world W), K worlds made",
and each best world the engine names is selected and previewed; the best world gets better (it
comes nearer the goal than any sampled world, by the module's score) and boxes met never go down. A second seek is stopped with Esc: every
world made stays. Full-window screenshots show the sidebar's Many Worlds tab at its default
width. Exit code 0 = pass.
"""
import json
import os
import re
import sys

import bpy
from bpy_extras.view3d_utils import location_3d_to_region_2d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds import _native, scene_boxes  # noqa: E402
from many_worlds.core import engine as engine_process  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from viewport_helpers import run_steps, viewport  # noqa: E402

OUT_DIR = sys.argv[sys.argv.index("--") + 1]
TICK_S = 0.15
HALF_PX = 12
# One box per dropped body, around where it ends in these worlds.
GOAL_WORLDS = (1, 2, 3)
# Below the sidebar's top: its first panel header, a folded panel's height, and the Many Worlds
# tab (after Item, Tool, View); factory settings, UI scale 1.
HEADER_BELOW_TOP_PX = 15
FOLDED_PANEL_PX = 28
TAB_BELOW_TOP_PX = 182


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
    """The sidebar on the Many Worlds tab, with Sampling, Worlds and Refine folded so the Query
    Boxes panel is at the top (clicks, as a user would; Blender 3.4 has no Python for either)."""
    area.spaces.active.show_region_ui = True
    area.tag_redraw()
    yield
    ui = next(r for r in area.regions if r.type == "UI")
    top = ui.y + ui.height
    yield from click(window, ui.x + ui.width - 14, top - TAB_BELOW_TOP_PX)
    for k in range(3):
        yield from click(window, ui.x + 60, top - HEADER_BELOW_TOP_PX - k * FOLDED_PANEL_PX)


def screenshot(window, area, region, name):
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.screenshot(filepath=os.path.join(OUT_DIR, name))


def end_rect(region, world, body):
    view = SESSION.view
    position = view.library.positions(world)[view.body_names.index(body), -1]
    x, y = (int(round(v)) for v in location_3d_to_region_2d(region, region.data, position))
    return (x - HALF_PX, y - HALF_PX, x + HALF_PX, y + HALF_PX)


def goal_value(world):
    """How far `world` gets towards the panel's goal (boxes met + closeness to the next one), by
    the module's own score of the boxes the add-on queries with."""
    lq = scene_boxes.library_query()
    boxes = [lq.native_box(spec) for spec in scene_boxes.enabled_specs(bpy.context.scene, SESSION.view)]
    return lq.index.score(world, boxes)["value"]


def best_of_view():
    """(boxes met, goal value) of the best world of the library as it is."""
    met = int(scene_boxes.library_query().result.boxes_satisfied.max())
    return met, max(goal_value(w) for w in SESSION.view.world_indices)


def steps():
    results = {}
    window, area, region = viewport()
    scene = bpy.context.scene
    settings = scene.mwb
    assert SESSION.view is not None, "no library on load"
    r3d = area.spaces.active.region_3d
    r3d.view_location = (0.6, 0.0, 0.3)
    r3d.view_distance = 3.0
    yield from show_query_panel(window, area)

    # The goal, drawn through this view: each body ends where it ended in another world.
    for body, world in zip(("Box0", "Box1", "Box2"), GOAL_WORLDS):
        with bpy.context.temp_override(window=window, area=area, region=region):
            assert bpy.ops.mwb.add_box(rect=end_rect(region, world, body), bodies=body) == {"FINISHED"}
    settings.boxes[2].after = "0"
    assert settings.boxes[2].after_box == 0
    first_met, first_value = best_of_view()
    assert first_met < 3, "no sampled world should meet the whole goal yet"
    results.update(first_met=first_met, first_value=first_value)
    stored = len(SESSION.view.world_indices)

    settings.seek_want, settings.threads = 1, 1
    assert settings.seek_budget_worlds == 2000, "the panel's default budget"
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.seek("INVOKE_DEFAULT") == {"RUNNING_MODAL"}, SESSION.status
    run = SESSION.engine
    assert run is not None and SESSION.run_label == "Seeking"
    shown, shot = [], False
    while SESSION.engine is not None:
        yield
        # What the panel says is the best world, and the world selected in the list at that moment.
        said = re.match(r"Seeking: best (\d+) of 3 boxes \(world (\d+)\), ([\d,]+) worlds made", SESSION.status)
        if said:
            shown.append((int(said[1]), int(said[2]), settings.selected_world))
            if not shot and len(SESSION.view.world_indices) > stored:
                screenshot(window, area, region, "seeking.png")
                shot = True
    assert SESSION.last_error == "", SESSION.last_error
    outcome = engine_process.parse_seek_outcome(run.summary())
    made = len(SESSION.view.world_indices) - stored
    assert outcome is not None and made == outcome.worlds_made > 0, (run.summary(), made)
    assert [item.world_index for item in settings.worlds] == SESSION.view.world_indices
    # The best world the panel names is the one selected; it changed while the seek ran, and the
    # boxes it meets never went down.
    assert shown and all(best == selected for _, best, selected in shown), shown
    assert len({best for _, best, _ in shown} | {outcome.best}) > 1, shown
    assert goal_value(outcome.best) > first_value, (goal_value(outcome.best), first_value)
    assert [met for met, _, _ in shown] == sorted(met for met, _, _ in shown) and shown[0][0] >= first_met, shown
    assert settings.selected_world == outcome.best and settings.previewing, (settings.selected_world, outcome)
    met_by_best = int(scene_boxes.library_query().result.boxes_satisfied[
        SESSION.view.world_indices.index(outcome.best)])
    assert met_by_best == outcome.best_boxes_met, (met_by_best, outcome)
    assert SESSION.status == engine_process.seek_outcome_text(outcome, 1), SESSION.status
    yield
    screenshot(window, area, region, "seek_ended.png")
    results.update(shown=shown, outcome=outcome.__dict__, status=SESSION.status)

    # A long seek stopped with Esc keeps every world it made.
    before = len(SESSION.view.world_indices)
    settings.seek_budget_worlds = 100000
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.seek("INVOKE_DEFAULT") == {"RUNNING_MODAL"}, SESSION.status
    while SESSION.engine is not None and len(SESSION.view.world_indices) < before + 16:
        yield
    simulate(window, "MOUSEMOVE", "NOTHING", region.x + 300, region.y + 300)
    yield
    simulate(window, "ESC", "PRESS", region.x + 300, region.y + 300)
    yield
    simulate(window, "ESC", "RELEASE", region.x + 300, region.y + 300)
    while SESSION.engine is not None:
        yield
    stored_now = len(_native.Library(SESSION.view.path).world_indices)
    assert SESSION.status.startswith("Seek cancelled: best"), SESSION.status
    assert before + 16 <= stored_now == len(SESSION.view.world_indices) < before + 100000, stored_now
    yield
    screenshot(window, area, region, "seek_cancelled.png")
    results.update(cancelled_status=SESSION.status)
    with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
        json.dump(results, f, indent=1)
    print("seek results:", results)


run_steps(steps, TICK_S)
