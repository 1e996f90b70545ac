"""Viewport test with the real UI under Xvfb: a scene of twelve bodies with long names, as an
animator's scene has, in the sidebar at its default width.

Run by `tests/viewport/run.sh test_many_bodies.py` (the fixture of test_paths_drawn: a ground and
three boxes). Nine more objects join the rigid bodies, every body gets a long name, and Sample is
pressed as its button presses it. Every panel of the add-on is then drawn through a recording
layout (sidebar_recording) and each text measured against its width: the legend names every
object whole, the ranking's summed Time to Rest tells the worlds apart, and no text is cut. No two
of the twelve objects share a colour. Full-window screenshots of the sidebar's top, the ranking
and the legend are kept. Exit code 0 = pass.
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds import scene_boxes  # noqa: E402
from many_worlds.core import palette  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.ui import legend  # noqa: E402
from sidebar_recording import measure, record_panels, redraw_all, scroll, show_many_worlds_tab, texts, \
    window_screenshot  # noqa: E402
from viewport_helpers import no_tooltips, run_steps, viewport  # noqa: E402

TICK_S = 0.3
LONG_NAMES = ["Oak_Barrel_Left_Stack", "Oak_Barrel_Right_Stack", "Wooden_Crate_Top_Shelf", "Wooden_Crate_Floor",
              "Iron_Cannonball_Small", "Iron_Cannonball_Large", "Glass_Bottle_Green", "Glass_Bottle_Brown",
              "Clay_Pot_With_Handle", "Stone_Block_Corner", "Copper_Kettle_Spout", "Straw_Basket_Woven"]


def add_bodies(window, area, region):
    """Nine copies of Box0 beside the others, made Active rigid bodies; then every body renamed."""
    scene = bpy.context.scene
    source = bpy.data.objects["Box0"]
    for k in range(9):
        ob = source.copy()
        ob.data = source.data.copy()
        ob.location = (-0.9 + 0.3 * (k % 3), 0.6 + 0.3 * (k // 3), 1.2 + 0.1 * k)
        scene.collection.objects.link(ob)
        if ob.rigid_body is None:
            with bpy.context.temp_override(window=window, area=area, region=region, object=ob, active_object=ob,
                                           selected_objects=[ob], selected_editable_objects=[ob]):
                bpy.ops.rigidbody.object_add(type="ACTIVE")
        elif ob.name not in scene.rigidbody_world.collection.objects:
            scene.rigidbody_world.collection.objects.link(ob)
    movers = sorted((ob for ob in scene.objects if ob.rigid_body is not None and ob.rigid_body.type == "ACTIVE"),
                    key=lambda ob: ob.name)
    assert len(movers) == 12, [ob.name for ob in movers]
    for ob, name in zip(movers, LONG_NAMES):
        ob.name = name
    bpy.context.view_layer.update()


def steps():
    window, area, region = viewport()
    scene = bpy.context.scene
    record_panels()
    no_tooltips()
    area.spaces.active.show_region_ui = True
    yield
    yield from show_many_worlds_tab(window, area)
    add_bodies(window, area, region)
    scene.mwb.world_count = 12
    for ob in bpy.data.objects:
        ob.select_set(False)
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.sample("INVOKE_DEFAULT") == {"RUNNING_MODAL"}, SESSION.status
    while SESSION.run is not None:
        yield
    assert SESSION.last_error == "", SESSION.last_error
    assert sorted(SESSION.view.body_names) == sorted(LONG_NAMES + ["Ground"]), SESSION.view.body_names
    # Ranked by Time to Rest summed over every body: values of several tens of seconds.
    scene.mwb.rank_metric, scene.mwb.rank_combine, scene.mwb.rank_bodies = "time_to_rest_s", "SUM", "SIMULATED"
    yield
    redraw_all()
    results = [measure("twelve_bodies_top")]
    window_screenshot("twelve_bodies_top.png")
    colours = palette.object_colours(SESSION.view.body_names, SESSION.view.simulated_bodies())
    assert len({colours[name] for name in LONG_NAMES}) == 12, "two of the twelve objects share a colour"
    # The legend gives each long name a row of its own rather than cutting it.
    entries = [name for name, _ in legend.legend_entries(bpy.context)]
    paths_text = " ".join(texts("Paths"))
    assert entries and all(name in paths_text for name in entries), (entries, paths_text)
    yield from scroll(window, area, "UI", steps=26)
    redraw_all()
    results.append(measure("twelve_bodies_ranking"))
    window_screenshot("twelve_bodies_ranking.png")
    # Rows whose worlds' values differ read differently (the rows shown, top down).
    shown = [text for text in texts("Worlds & Ranking") if text.endswith(" s")]
    ranked = scene_boxes.RANKING.get(bpy.context).values[:len(shown)]
    print("ranking values:", shown, list(ranked))
    assert len(shown) >= 6, shown
    for k in range(len(shown) - 1):
        if abs(ranked[k + 1] - ranked[k]) > 1e-4:
            assert shown[k] != shown[k + 1], f"rows {k + 1} and {k + 2} differ but read alike: {shown}"
    yield from scroll(window, area, "UI")
    redraw_all()
    results.append(measure("twelve_bodies_legend"))
    window_screenshot("twelve_bodies_legend.png")
    for result in results:
        print(f"{result['state']}: tightest {result['tightest']}; cut: {result['cut']}")
    cut = [(r["state"], *c) for r in results for c in r["cut"]]
    assert not cut, f"text cut at the default sidebar width (state, panel, text, needed px, has px): {cut}"


run_steps(steps, TICK_S)
