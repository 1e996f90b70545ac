"""Refinement in the sidebar on a scene as an animator makes it: cubes, UV spheres and a cylinder
added with Blender's operators and left at the default shape (Convex Hull), over a plane that
collides as a mesh. Every child is stored by the supervised workers, and the panel's last line
counts what was stored and, when worlds are lost, how many and why."""
import os
import sys
import time

import bpy
import pytest

from conftest import ROOT, add_rigid_body, mesh_object, override, save_blend, sample_and_wait
from test_refining import refine_and_wait

from many_worlds.core.session import SESSION


def default_shapes_scene():
    plane = mesh_object("Plane", primitive="plane", size=20)
    add_rigid_body(plane, "PASSIVE", shape="MESH")
    objects = []
    for i in range(4):
        objects.append(mesh_object(f"Cube.{i:03d}", location=(-1.5 + 1.1 * i, 1.0, 0.6 + 0.4 * i), size=0.5))
    objects.append(mesh_object("Sphere", primitive="uv_sphere", location=(-0.4, 0.9, 3.0), radius=0.3))
    objects.append(mesh_object("Sphere.001", primitive="uv_sphere", location=(1.2, -0.8, 2.0), radius=0.25))
    objects.append(mesh_object("Cylinder", primitive="cylinder", location=(0, -1.5, 0.5), radius=0.2, depth=0.6))
    for ob in objects:
        with override(ob):
            bpy.ops.rigidbody.object_add(type="ACTIVE")
        assert ob.rigid_body.collision_shape == "CONVEX_HULL", "Blender's default shape"
        v = ob.mwb_variation
        v.location_min, v.location_max = (-0.2, -0.2, 0), (0.2, 0.2, 0.2)
        v.angular_velocity_min, v.angular_velocity_max = (-3, -3, -3), (3, 3, 3)
    scene = bpy.context.scene
    scene.rigidbody_world.point_cache.frame_start = 1
    scene.rigidbody_world.point_cache.frame_end = 49
    scene.frame_start, scene.frame_end = 1, 49


@pytest.fixture
def sampled(tmp_path):
    default_shapes_scene()
    save_blend(tmp_path)
    sample_and_wait(8, threads=2, seed=3)
    assert len(SESSION.view.world_indices) == 8
    return SESSION.view


def test_refining_a_default_shape_sphere_stores_every_child(sampled):
    from many_worlds.operators import run_poller
    seen = []
    poll = run_poller.poll_run

    def watching_poll():
        interval = poll()
        seen.append(SESSION.status)
        return interval

    run_poller.poll_run = watching_poll
    try:
        _, children = refine_and_wait(sampled.world_indices[2], "Sphere", 0.4, count=8)
    finally:
        run_poller.poll_run = poll
    # Until the engine says how many worlds it makes, the panel keeps the line the run began with.
    assert seen and not any(" 0 / 0 " in line or line.endswith(" / 0 worlds") for line in seen), seen
    assert len(children) == 8
    assert SESSION.status.startswith("Refined into 8 worlds;"), SESSION.status
    assert "rejected" not in SESSION.status and SESSION.run_warnings == []


@pytest.fixture
def a_child_crashes():
    # Child 10 makes its worker abort, as a world that crashes ODE would (a test-only switch).
    os.environ["MWB_ENGINE_TEST_FAULTS"] = "10:abort"
    yield
    del os.environ["MWB_ENGINE_TEST_FAULTS"]


def test_a_refinement_that_loses_a_world_says_how_many_and_why(sampled, a_child_crashes):
    _, children = refine_and_wait(sampled.world_indices[1], "Sphere.001", 0.3, count=8)
    assert len(children) == 7 and 10 not in children
    assert SESSION.status.startswith("Refined into 7 worlds; 1 rejected (1: the simulation crashed"), SESSION.status
    assert "Aborted" in SESSION.status and SESSION.status.endswith("the library holds 15"), SESSION.status


def test_seeking_on_default_shapes_stores_every_world_and_counts_them(sampled):
    """A box where the sphere ends in one world, over the run's last second, as the goal: the
    search's worlds are made by supervised workers, none is rejected, and the last line counts
    the worlds it made."""
    from test_queries import PROJECTION, SIZE, VIEW
    from test_refining import rect_around
    from many_worlds.core import engine as engine_process
    from many_worlds.operators import run_poller
    world = sampled.world_indices[4]
    last_s = (sampled.library.world_info(world).frame_count - 1) / sampled.library.world_info(world).record_hz
    rect = rect_around(world, "Sphere", last_s, half_px=40)
    assert bpy.ops.mwb.add_box(rect=rect, bodies="Sphere", view_matrix=VIEW.ravel().tolist(),
                               projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE) == {"FINISHED"}
    box = bpy.context.scene.mwb.boxes[-1]
    box.use_time_window, box.time_start_s, box.time_end_s = True, last_s - 1.0, last_s
    settings = bpy.context.scene.mwb
    settings.seek_want, settings.seek_budget_worlds, settings.threads = 50, 40, 2
    assert bpy.ops.mwb.seek() == {"FINISHED"}
    run = SESSION.run
    deadline = time.monotonic() + 120
    while run_poller.poll_run() is not None:
        assert time.monotonic() < deadline, "the seek stalled"
        time.sleep(0.05)
    outcome = engine_process.SeekOutcome.from_summary(run.summary())
    assert SESSION.last_error == "" and outcome is not None, SESSION.status
    assert outcome.worlds_made == 40 and outcome.rejected == 0
    assert len(SESSION.view.world_indices) == 8 + 40
    assert SESSION.status == outcome.text and "; 40 worlds made in " in SESSION.status, SESSION.status
    assert "rejected" not in SESSION.status


def cell_fracture_available():
    import addon_utils
    return any(module.__name__ == "object_fracture_cell" for module in addon_utils.modules())


@pytest.mark.skipif(not cell_fracture_available(), reason="Cell Fracture is bundled with Blender up to 4.1 only")
def test_refining_a_cell_fracture_wall_on_a_mesh_floor_stores_every_child(tmp_path):
    """The fidelity corpus's wall, cut by Blender's Cell Fracture into hull pieces joined by
    breakable FIXED constraints, on a passive MESH plane, a ball thrown at it: a piece refined in
    the sidebar gets every child, none rejected."""
    sys.path.insert(0, os.path.join(ROOT, "tests", "fidelity"))
    import scenes
    scenes.fracture_wall(ground_shape="MESH")
    save_blend(tmp_path)
    sample_and_wait(4, threads=2, seed=1)
    assert len(SESSION.view.world_indices) == 4
    _, children = refine_and_wait(SESSION.view.world_indices[1], "Wall_cell.008", 0.3, count=8)
    assert len(children) == 8
    assert SESSION.status.startswith("Refined into 8 worlds;") and "rejected" not in SESSION.status, SESSION.status
