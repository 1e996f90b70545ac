"""Viewport test with the real UI under Xvfb: the change-and-resample loop.

Run by `tests/viewport/run.sh test_resample_loop.py`. A variation range is changed and Sample is
pressed as its button presses it: the worlds go into a new library beside the first one, which
is kept; the Sampling panel lists both, and choosing the first one in the list opens it again.
Full-window screenshots of the Sampling panel are kept. Exit code 0 = pass.
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from many_worlds import _native  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from viewport_helpers import run_steps, viewport  # noqa: E402

OUT_DIR = sys.argv[sys.argv.index("--") + 1]
TICK_S = 0.15


def simulate(window, region, kind, value, x, y):
    window.event_simulate(type=kind, value=value, x=region.x + int(x), y=region.y + int(y))


def sampling_panel_screenshot(name):
    """The Sampling panel as a popup over the viewport (Blender 3.4 cannot switch the sidebar's
    tab from Python), in a full-window screenshot."""
    window, area, region = viewport()
    simulate(window, region, "MOUSEMOVE", "NOTHING", 320, region.height - 60)
    yield
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.wm.call_panel(name="MWB_PT_sampling", keep_open=True)
    yield
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.screenshot(filepath=os.path.join(OUT_DIR, name))
    simulate(window, region, "ESC", "PRESS", 320, region.height - 60)
    yield
    simulate(window, region, "ESC", "RELEASE", 320, region.height - 60)
    yield


def steps():
    window, area, region = viewport()
    scene = bpy.context.scene
    settings = scene.mwb
    first_library = SESSION.view.path
    first_worlds = list(SESSION.view.world_indices)
    assert first_worlds, "the fixture has a sampled library"
    # A changed range: the old library holds another run now.
    bpy.data.objects["Box0"].mwb_variation.location_max[2] += 0.2
    settings.world_count = 4
    with bpy.context.temp_override(window=window, area=area, region=region):
        assert bpy.ops.mwb.sample("INVOKE_DEFAULT") == {"RUNNING_MODAL"}, SESSION.status
    while SESSION.run is not None:
        yield
    assert SESSION.last_error == "", SESSION.last_error
    second_library = SESSION.view.path
    assert second_library != first_library and os.path.basename(second_library) == "paths-2.mwb", second_library
    assert sorted(SESSION.view.world_indices) == [0, 1, 2, 3]
    assert sorted(_native.Library(first_library).world_indices) == sorted(first_worlds), "the old library is kept"
    assert len(settings.libraries) == 2 and settings.library_index == 1
    yield from sampling_panel_screenshot("two_libraries.png")
    # Choosing the first library in the list opens it again, with its worlds.
    settings.library_index = 0
    yield
    assert SESSION.view.path == first_library, SESSION.view.path
    assert [item.world_index for item in settings.worlds] == SESSION.view.world_indices
    assert sorted(SESSION.view.world_indices) == sorted(first_worlds)
    yield from sampling_panel_screenshot("back_to_first.png")
    print("resample loop: libraries", [item.path for item in settings.libraries])


run_steps(steps, TICK_S)
