"""Viewport test with the real UI under Xvfb: the path overlay is drawn.

Run by tests/viewport/run.sh:
  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --addons many_worlds paths.blend \
      --python tests/viewport/test_paths_drawn.py -- OUT_DIR
The add-on reopens the library on load (load_post). Screenshots of the window are taken with the
paths on, with a world selected, behind a wall and with the wall hidden, with the selected
world's paths drawn alone, with the paths off and with no world selected; the 3D viewport's pixels
must show each box's path colour (and the selected world's colour) only while drawing is on. Where the
selected world shows drawn alone, it must still show among the other paths, and behind a wall as
with the wall hidden: it is drawn on top. With a budget of an eighth of the
vertices, fewer paths are drawn and the panel's line names the subset; plain redraws do not
rebuild the batches, and the paths drawn are thinned for the view (core.screen_thinning). The
label naming the selected world (in the selected world's colour, bottom-left) must be drawn there
only while a world is selected.
Exit code 0 = pass.
"""
import json
import os
import sys

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.core import palette, path_budget  # noqa: E402
from many_worlds.draw import paths, world_label  # noqa: E402
from viewport_helpers import colour_mask, viewport  # noqa: E402
import viewport_helpers  # noqa: E402

OUT_DIR = sys.argv[sys.argv.index("--") + 1]
TICK_S = 0.5


def screenshot(name):
    return viewport_helpers.screenshot(OUT_DIR, name)


def label_corner(rgb):
    """A mask of the bottom-left corner where the world label is drawn (region pixels, bottom row 0)."""
    window, area, region = viewport()
    with bpy.context.temp_override(window=window, area=area, region=region):
        x, y = world_label.label_origin(bpy.context)
    scale = bpy.context.preferences.view.ui_scale
    corner = np.zeros(rgb.shape[:2], dtype=bool)
    corner[:int(y + 40 * scale), :int(x + 420 * scale)] = True
    return corner


# The selected world's pixels of each screenshot (outside the label's corner), for pixel-wise
# comparisons of one screenshot with another.
SELECTED_PIXELS = {}


def counts(rgb, name=None):
    """Pixels of each object's colour (Box0, Box1, Box2: the first three of the palette; matching
    is Box0's), of anything drawn outside the label's corner, of the selected world's colour
    outside the corner (its paths) and inside it (the label)."""
    corner = label_corner(rgb)
    selected = colour_mask(rgb, paths.SELECTED_COLOR)
    if name:
        SELECTED_PIXELS[name] = (selected & ~corner, rgb[..., :3])
    objects = [int(colour_mask(rgb, palette.PALETTE[k]).sum()) for k in range(4)]
    lit = rgb.max(axis=-1) > 0.05
    return {"matching": objects[0], "objects": objects, "lit": int((lit & ~corner).sum()),
            "selected": int((selected & ~corner).sum()), "label": int((selected & corner).sum())}


def hidden_fraction(alone, among):
    """The share of the selected world's pixels in screenshot `alone` that another colour covers
    in screenshot `among`. The lines' anti-aliased rims blend with whatever lies under them, so a
    pixel counts as covered only if it is far from the selected colour."""
    shown, _ = SELECTED_PIXELS[alone]
    _, rgb = SELECTED_PIXELS[among]
    near = np.all(np.abs(rgb - np.array(paths.SELECTED_COLOR[:3])) < 0.3, axis=-1)
    return float((shown & ~near).sum()) / max(1, int(shown.sum()))


def add_wall(r3d):
    """A cube halfway between the view's eye and its centre, wide enough to cover every path."""
    eye = r3d.view_matrix.inverted().translation
    centre = Vector(r3d.view_location)
    mesh = bpy.data.meshes.new("Wall")
    corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    mesh.from_pydata(corners, [], faces)
    wall = bpy.data.objects.new("Wall", mesh)
    bpy.context.scene.collection.objects.link(wall)
    wall.location = centre.lerp(eye, 0.5)
    wall.scale = (1.2, 1.2, 1.2)
    return wall


def steps():
    """Each yield waits one tick so the viewport redraws before the next screenshot."""
    results = {}
    scene = bpy.context.scene
    window, area, region = viewport()
    assert SESSION.view is not None, "the library was not reopened on load"
    assert len(SESSION.view.world_indices) > 0
    r3d = area.spaces.active.region_3d
    r3d.view_location = (0.6, 0.0, 0.5)
    r3d.view_distance = 4.0
    # Hide the grid and the floor so only the overlay can produce coloured lines.
    area.spaces.active.overlay.show_floor = False
    for ob in bpy.data.objects:
        ob.select_set(False)
    scene.mwb.path_width = 3.0
    area.tag_redraw()
    yield
    results["paths_on"] = counts(screenshot("paths_on.png"))
    # Once the view has stood still for a poll, the paths are rebuilt thinned for it (for the view
    # as last drawn: under load the region may still change size as the window lays out).
    def thinned_for_the_view():
        drawn = list(paths.OVERLAY._views.values())
        arrays = paths.OVERLAY.arrays
        return arrays is not None and arrays.screen is not None and drawn == [arrays.screen]

    for _ in range(60):
        if thinned_for_the_view():
            break
        area.tag_redraw()
        yield
    results["thinned_on_screen"] = paths.OVERLAY.arrays.screen is not None
    # From then on, plain redraws of the still view reuse the batches.
    rebuilds, key_before = paths.OVERLAY.rebuilds, paths.OVERLAY._key
    for _ in range(3):
        area.tag_redraw()
        yield
    results["rebuilds_on_redraw"] = paths.OVERLAY.rebuilds - rebuilds
    if results["rebuilds_on_redraw"]:  # which input changed, for the failure message
        results["inputs_changed"] = [str(a) + " -> " + str(b) for a, b in zip(key_before, paths.OVERLAY._key) if a != b]
    # A budget of an eighth of the vertices: fewer paths drawn, and the panel's line. (With a
    # quarter, thinning keeps most paths and their pixels within a few percent of the bound.)
    paths.OVERLAY.vertex_budget = paths.OVERLAY.arrays.vertex_count // 8
    area.tag_redraw()
    yield
    results["budget"] = counts(screenshot("budget.png"))
    results["budget_text"] = paths.OVERLAY.budget_text()
    results["budget_vertices"] = [paths.OVERLAY.arrays.vertex_count, paths.OVERLAY.vertex_budget]
    paths.OVERLAY.vertex_budget = path_budget.VERTEX_BUDGET
    bpy.ops.mwb.select_world(world=SESSION.view.world_indices[0])
    area.tag_redraw()
    yield
    results["world_selected"] = counts(screenshot("world_selected.png"), "world_selected")
    # A wall between the eye and every path hides the depth-tested ones: the selected world's paths
    # show as many pixels as with the wall hidden.
    wall = add_wall(r3d)
    area.tag_redraw()
    yield
    results["behind_wall"] = counts(screenshot("behind_wall.png"), "behind_wall")
    wall.hide_set(True)
    area.tag_redraw()
    yield
    results["wall_hidden"] = counts(screenshot("wall_hidden.png"), "wall_hidden")
    bpy.data.objects.remove(wall)
    # The selected world's batch alone (the cache keeps it until its inputs change).
    paths.OVERLAY._batches = [b for b in paths.OVERLAY._batches if b[2]]
    area.tag_redraw()
    yield
    results["selected_alone"] = counts(screenshot("selected_alone.png"), "selected_alone")
    paths.OVERLAY.clear()
    scene.mwb.show_paths = False
    area.tag_redraw()
    yield
    results["paths_off"] = counts(screenshot("paths_off.png"))
    scene.mwb.selected_world = -1
    area.tag_redraw()
    yield
    results["none_selected"] = counts(screenshot("none_selected.png"))
    # The panels draw in the real UI (a drawing error would print a traceback, which run.sh fails on):
    # the variation panel next to the Rigid Body settings, the sidebar with the sampling panel.
    properties = next(a for a in window.screen.areas if a.type == "PROPERTIES")
    bpy.context.view_layer.objects.active = bpy.data.objects["Box0"]
    properties.spaces.active.context = "PHYSICS"
    area.spaces.active.show_region_ui = True
    area.tag_redraw()
    # Blender 4.x lets a script pick the sidebar tab only once the sidebar has drawn its tabs.
    yield
    sidebar = next(r for r in area.regions if r.type == "UI")
    if hasattr(sidebar, "active_panel_category"):
        sidebar.active_panel_category = "Many Worlds"
    properties.tag_redraw()
    area.tag_redraw()
    yield
    screenshot("panels.png")
    results["hidden_by_others"] = hidden_fraction("selected_alone", "world_selected")
    results["hidden_by_wall"] = hidden_fraction("wall_hidden", "behind_wall")
    with open(os.path.join(OUT_DIR, "result.json"), "w") as f:
        json.dump(results, f, indent=1)
    print("viewport pixel counts:", results)
    assert results["paths_on"]["matching"] > 300, results
    # Each box's paths in its own colour, and no paths in a colour no object has.
    assert min(results["paths_on"]["objects"][:3]) > 300 and results["paths_on"]["objects"][3] < 20, results
    assert results["rebuilds_on_redraw"] == 0, results
    # Once the view stood still the paths were thinned for it, and still show each box's colour.
    assert results["thinned_on_screen"], results
    assert results["world_selected"]["selected"] > 100, results
    # Neither the other paths nor the scene hide the selected world: where it shows drawn alone,
    # it still shows among the others.
    assert results["hidden_by_others"] < 0.03, results
    # Nor does the scene's geometry: a wall hides the other paths, not the selected world's.
    under, through = results["behind_wall"], results["wall_hidden"]
    assert under["lit"] < through["lit"] - 2000, results
    assert through["selected"] > 100 and results["hidden_by_wall"] < 0.03, results
    # The others are dimmed while a world is selected: few pixels keep the full matching colour.
    assert results["world_selected"]["matching"] < 0.5 * results["paths_on"]["matching"], results
    budget_objects, all_objects = sum(results["budget"]["objects"]), sum(results["paths_on"]["objects"])
    assert 0.05 * all_objects < budget_objects < 0.8 * all_objects, results
    assert results["budget_text"].startswith("Showing ") and results["budget_text"].endswith("(drawing budget)")
    assert results["budget_vertices"][0] <= results["budget_vertices"][1], results
    assert results["paths_off"]["matching"] < 20 and results["paths_off"]["selected"] < 20, results
    # The label: drawn with a world selected (paths on or off), gone without one.
    assert results["paths_on"]["label"] < 5 and results["none_selected"]["label"] < 5, results
    assert results["world_selected"]["label"] > 50 and results["paths_off"]["label"] > 50, results


viewport_helpers.run_steps(steps, TICK_S)
