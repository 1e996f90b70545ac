"""Viewport test with the real UI under Xvfb: the refine tool driven by simulated mouse events.

Run by `tests/viewport/run.sh test_refine_tool.py`. With a world selected and Box0 selected, the
tool is started as the sidebar button starts it and a left-drag draws a box over part of Box0's
path; on release the engine child refines the world and the children stream in through the
timer poller while the UI runs. Their branch time is where Box0's path first enters the box (a
direct PathIndex lookup through the region's view). A second refinement of a child is cancelled
with Esc: the finished grandchildren stay. Box2 is then removed from the child with Remove from
Worlds, invoked as its button invokes it. Exit code 0 = pass.
"""
import json
import os
import sys

import bpy
import numpy as np
from bpy_extras.view3d_utils import location_3d_to_region_2d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds import _native  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.draw import boxes  # noqa: E402
from viewport_helpers import run_steps, viewport  # noqa: E402
import viewport_helpers  # noqa: E402

OUT_DIR = sys.argv[sys.argv.index("--") + 1]
TICK_S = 0.15
HALF_PX = 25
DRAG_STEPS = 4
BRANCH_AT_S = 0.3


def simulate(window, region, kind, value, x, y):
    window.event_simulate(type=kind, value=value, x=region.x + int(x), y=region.y + int(y))


def rect_on_path(region, world, body, time_s):
    """Whole-pixel rectangle around where `body` is at `time_s` in `world`."""
    view = SESSION.view
    info = view.library.world_info(world)
    position = view.library.positions(world)[view.body_names.index(body), int(round(time_s * info.record_hz))]
    x, y = (int(round(v)) for v in location_3d_to_region_2d(region, region.data, position))
    return (x - HALF_PX, y - HALF_PX, x + HALF_PX, y + HALF_PX)


def direct_first_time(region, world, body, rect):
    library = _native.Library(SESSION.view.path)
    scene = _native.Scene.from_json(library.header.scene_json)
    index = _native.PathIndex(_native.body_bounding_radii(scene))
    index.add_library(library)
    box = _native.QueryBox(np.array(region.data.view_matrix), np.array(region.data.window_matrix),
                           (region.width, region.height), rect, bodies=[scene.body_names.index(body)])
    return index.first_time_inside(world, [scene.body_names.index(body)], box)


def drag_refine_box(window, area, region, rect):
    x0, y0, x1, y1 = rect
    simulate(window, region, "MOUSEMOVE", "NOTHING", x0, y0)
    yield
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.refine_box("INVOKE_DEFAULT") == {"RUNNING_MODAL"}
    yield
    simulate(window, region, "LEFTMOUSE", "PRESS", x0, y0)
    yield
    for k in range(1, DRAG_STEPS + 1):
        simulate(window, region, "MOUSEMOVE", "NOTHING", x0 + (x1 - x0) * k / DRAG_STEPS,
                 y0 + (y1 - y0) * k / DRAG_STEPS)
        yield
    assert boxes.OVERLAY.dragging is not None and boxes.OVERLAY.dragging[1] == rect, boxes.OVERLAY.dragging
    simulate(window, region, "LEFTMOUSE", "RELEASE", x1, y1)
    yield


def steps():
    results = {}
    window, area, region = viewport()
    scene = bpy.context.scene
    assert SESSION.view is not None, "no library on load"
    r3d = area.spaces.active.region_3d
    r3d.view_location = (0.6, 0.0, 0.3)
    r3d.view_distance = 3.0
    area.spaces.active.show_region_ui = True
    area.tag_redraw()
    yield
    sampled = list(SESSION.view.world_indices)
    parent = sampled[3]
    bpy.ops.mwb.select_world(world=parent)
    for ob in bpy.data.objects:
        ob.select_set(ob.name == "Box0")
    scene.mwb.refine_count = 4
    yield
    rect = rect_on_path(region, parent, "Box0", BRANCH_AT_S)
    expected_t = direct_first_time(region, parent, "Box0", rect)
    assert 0 <= expected_t <= BRANCH_AT_S, expected_t
    for _ in drag_refine_box(window, area, region, rect):
        yield
    assert SESSION.run is not None and SESSION.runs[-1].label == "Refining", SESSION.status
    while SESSION.run is not None:
        yield
    assert SESSION.last_error == "", SESSION.last_error
    children = [w for w in SESSION.view.world_indices if w not in sampled]
    assert len(children) == 4, children
    assert [item.world_index for item in scene.mwb.worlds] == SESSION.view.world_indices
    branches = []
    for child in children:
        info = SESSION.view.library.world_info(child)
        assert info.parent_world == parent, info
        branches.append(info.branch_time_s)
        assert expected_t - 1 / info.record_hz - 1e-9 <= info.branch_time_s <= expected_t + 1e-9, info
    results.update(parent=parent, children=children, expected_t=expected_t, branches=branches)

    # The family of the parent in the list and the viewport (the others dimmed).
    scene.mwb.family_only = True
    area.tag_redraw()
    yield
    viewport_helpers.screenshot(OUT_DIR, "family.png")

    # Refine a child into many worlds and press Esc once two have landed: they stay.
    child = children[0]
    bpy.ops.mwb.select_world(world=child)
    for ob in bpy.data.objects:
        ob.select_set(ob.name == "Box1")
    scene.mwb.refine_count, scene.mwb.threads = 5000, 1
    yield
    rect = rect_on_path(region, child, "Box1", 0.2)
    for _ in drag_refine_box(window, area, region, rect):
        yield
    assert SESSION.run is not None, SESSION.status
    while SESSION.run is not None and SESSION.run.progress()[0] < 2:
        yield
    simulate(window, region, "ESC", "PRESS", 300, 300)
    yield
    simulate(window, region, "ESC", "RELEASE", 300, 300)
    while SESSION.run is not None:
        yield
    grandchildren = [w for w in SESSION.view.world_indices
                     if SESSION.view.lineages()[w].parent == child]
    assert 2 <= len(grandchildren) < 5000 and "cancelled" in SESSION.status, (len(grandchildren), SESSION.status)
    results["grandchildren_kept"] = len(grandchildren)

    # Remove from Worlds as its button starts it: the children without Box2 stream in while the UI runs.
    bpy.ops.mwb.select_world(world=child)
    for ob in bpy.data.objects:
        ob.select_set(ob.name == "Box2")
    scene.mwb.refine_count = 3
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.remove_from_worlds("INVOKE_DEFAULT") == {"RUNNING_MODAL"}
    assert SESSION.runs[-1].label == "Removing", SESSION.status
    while SESSION.run is not None:
        yield
    assert SESSION.last_error == "", SESSION.last_error
    box2 = SESSION.view.body_names.index("Box2")
    without = [w for w in SESSION.view.world_indices if SESSION.view.lineages()[w].removed == (box2,)]
    assert len(without) == 3 and not any(SESSION.view.present(w)[box2] for w in without), without
    assert all(SESSION.view.lineages()[w].parent == child for w in without)
    bpy.ops.mwb.select_world(world=without[0])
    area.tag_redraw()
    yield
    viewport_helpers.screenshot(OUT_DIR, "removed.png")
    results["removed_children"] = without

    # Go to Parent from a grandchild, then the refine panel as a popup (drawing errors fail run.sh).
    bpy.ops.mwb.select_world(world=grandchildren[0])
    assert bpy.ops.mwb.go_to_parent() == {"FINISHED"} and scene.mwb.selected_world == child
    simulate(window, region, "MOUSEMOVE", "NOTHING", 300, region.height - 80)
    yield
    for panel in ("MWB_PT_worlds", "MWB_PT_refine"):
        with bpy.context.temp_override(window=window, area=area, region=region):
            bpy.ops.wm.call_panel(name=panel, keep_open=True)
        yield
        viewport_helpers.screenshot(OUT_DIR, f"{panel}.png")
        simulate(window, region, "ESC", "PRESS", 300, region.height - 80)
        yield
        simulate(window, region, "ESC", "RELEASE", 300, region.height - 80)
        yield
    with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
        json.dump(results, f, indent=1)
    print("refine tool results:", results)


run_steps(steps, TICK_S)
