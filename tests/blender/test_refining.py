"""Refinement through the add-on: the refine operator finds where the selected objects first enter
a box in the selected world and runs the real engine child; children stream into the view and the
list, cancel keeps the finished ones, Go to Parent and the family filter follow the lineage."""
import time

import bpy
import numpy as np
import pytest

from conftest import cancel_after_finished, drop_scene, sample_and_wait, save_blend
from test_queries import PROJECTION, SIZE, VIEW, to_screen

from many_worlds import _native
from many_worlds.core import family as core_family
from many_worlds.core.session import SESSION
from many_worlds.operators import run_poller
from many_worlds.ui import lists


@pytest.fixture
def sampled(tmp_path):
    drop_scene(bodies=2)
    save_blend(tmp_path)
    sample_and_wait(4, threads=2, seed=5)
    return SESSION.view


def select_only(*names):
    for ob in bpy.context.view_layer.objects:
        ob.select_set(ob.name in names)
    bpy.context.view_layer.objects.active = bpy.data.objects[names[0]]


def rect_around(world, body, time_s, half_px=12):
    """A screen rectangle around where `body` is at `time_s` in `world` (test camera)."""
    view = SESSION.view
    info = view.library.world_info(world)
    frame = int(round(time_s * info.record_hz))
    position = view.library.positions(world)[view.body_names.index(body), frame]
    x, y = to_screen(position[None])[0]
    return (x - half_px, y - half_px, x + half_px, y + half_px)


def first_time_in_rect(world, body, rect):
    """t_min computed here from the decoded full-rate path: first recorded frame inside the rectangle."""
    view = SESSION.view
    info = view.library.world_info(world)
    screen = to_screen(view.library.positions(world)[view.body_names.index(body)])
    x0, y0, x1, y1 = rect
    inside = np.nonzero((screen[:, 0] >= x0) & (screen[:, 0] <= x1) & (screen[:, 1] >= y0) & (screen[:, 1] <= y1))[0]
    return inside[0] / info.record_hz if len(inside) else -1.0


def refine(rect):
    return bpy.ops.mwb.refine(rect=rect, view_matrix=VIEW.ravel().tolist(),
                              projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE)


def pump(timeout_s=120):
    deadline = time.monotonic() + timeout_s
    while run_poller.poll_run() is not None:
        assert time.monotonic() < deadline, "the engine run did not finish in time"
        time.sleep(0.05)


def refine_and_wait(world, body, time_s, count):
    bpy.ops.mwb.select_world(world=world)
    select_only(body)
    bpy.context.scene.mwb.refine_count = count
    rect = rect_around(world, body, time_s)
    assert refine(rect) == {"FINISHED"}
    assert SESSION.run is not None and SESSION.runs[-1].label == "Refining"
    before = set(SESSION.view.world_indices)
    pump()
    assert SESSION.last_error == "", SESSION.status
    return rect, sorted(set(SESSION.view.world_indices) - before)


def test_refine_creates_children_branching_where_the_objects_enter_the_box(sampled):
    parent = sampled.world_indices[1]
    rect, children = refine_and_wait(parent, "Box0", 0.3, count=3)
    assert len(children) == 3 and min(children) > max(range(4))
    # Streamed into the view and the list; the path index (synced when queried) takes them too.
    assert [w.world_index for w in bpy.context.scene.mwb.worlds] == SESSION.view.world_indices
    SESSION.query.sync()
    assert SESSION.query.index.world_count == 7
    t_ref = first_time_in_rect(parent, "Box0", rect)
    assert 0.2 < t_ref <= 0.3 + 1e-9
    library = _native.Library(SESSION.view.path)
    for child in children:
        info = library.world_info(child)
        assert info.parent_world == parent and info.root_world == parent
        branch = info.branch_time_s
        assert abs(branch - t_ref) <= 1 / 30, (branch, t_ref)
        # Snapped down to a recorded frame.
        assert abs(branch * info.record_hz - round(branch * info.record_hz)) < 1e-6
        assert branch <= t_ref + 1 / 30
        # Only the selected object was simulated anew before anything touched the other one.
        assert info.changed_bodies[SESSION.view.body_names.index("Box0")]
    assert "Refined into 3 worlds" in SESSION.status


def test_go_to_parent_and_the_family_filter_follow_the_lineage(sampled):
    root = sampled.world_indices[2]
    _, children = refine_and_wait(root, "Box0", 0.3, count=2)
    child = children[0]
    _, grandchildren = refine_and_wait(child, "Box1", 0.2, count=2)
    mwb = bpy.context.scene.mwb

    def listed():
        shown, _ = lists.family_rows(mwb, mwb.worlds)
        return {item.world_index for item, flag in zip(mwb.worlds, shown) if flag}

    mwb.family_only = True
    bpy.ops.mwb.select_world(world=child)
    assert listed() == {root, child, *grandchildren}
    relations = SESSION.view.family(child)
    assert relations[root] == core_family.ROOT and relations[child] == core_family.SELECTED
    assert all(relations[g] == core_family.CHILD for g in grandchildren)
    bpy.ops.mwb.select_world(world=grandchildren[1])
    assert listed() == {root, child, grandchildren[1]}
    assert SESSION.view.family(grandchildren[1])[child] == core_family.ANCESTOR
    bpy.ops.mwb.select_world(world=root)
    assert listed() == {root, *children}
    # The list orders the family root first, down to the children.
    flags, order = lists.family_rows(mwb, mwb.worlds)
    shown = sorted((order[k], item.world_index) for k, item in enumerate(mwb.worlds) if flags[k])
    assert shown[0][1] == root
    mwb.family_only = False
    assert lists.family_rows(mwb, mwb.worlds) is None
    assert core_family.relation_text(SESSION.view.lineages()[grandchildren[0]]).startswith(f"child of {child} at ")

    # Go to Parent walks back up, and stops at a sampled world.
    bpy.ops.mwb.select_world(world=grandchildren[0])
    assert bpy.ops.mwb.go_to_parent() == {"FINISHED"}
    assert mwb.selected_world == child and mwb.worlds[mwb.world_list_index].world_index == child
    assert bpy.ops.mwb.go_to_parent() == {"FINISHED"}
    assert mwb.selected_world == root
    assert not bpy.ops.mwb.go_to_parent.poll()


def test_a_box_the_objects_never_enter_reports_and_starts_nothing(sampled):
    world = sampled.world_indices[0]
    bpy.ops.mwb.select_world(world=world)
    select_only("Box0")
    # A corner of the view far above the scene: no path goes there.
    assert refine((0, SIZE[1] - 20, 20, SIZE[1])) == {"CANCELLED"}
    assert SESSION.run is None
    assert SESSION.status == f"the selected objects never enter that box in world {world}"
    assert len(_native.Library(SESSION.view.path).world_indices) == 4


def test_refining_needs_selected_simulated_objects_and_a_selected_world(sampled):
    select_only("Ground")
    bpy.ops.mwb.select_world(world=sampled.world_indices[0])
    with pytest.raises(RuntimeError, match="Select the objects to refine"):
        refine(rect_around(sampled.world_indices[0], "Box0", 0.3))
    assert SESSION.run is None


def test_cancel_keeps_finished_children_and_allows_one_run_at_a_time(tmp_path):
    drop_scene(bodies=2, frame_end=240)
    save_blend(tmp_path)
    sample_and_wait(1, threads=1, stop_at_rest=False)
    world = SESSION.view.world_indices[0]
    bpy.ops.mwb.select_world(world=world)
    select_only("Box0")
    mwb = bpy.context.scene.mwb
    mwb.refine_count, mwb.threads = 5000, 1
    assert refine(rect_around(world, "Box0", 0.2)) == {"FINISHED"}
    # One engine run at a time: neither sampling nor another refinement can start now.
    assert not bpy.ops.mwb.sample.poll() and not bpy.ops.mwb.refine.poll()
    cancel_after_finished(2)
    assert SESSION.run is None and SESSION.last_error == ""
    assert "Refining cancelled" in SESSION.status
    children = [w for w in SESSION.view.world_indices if w != world]
    assert 2 <= len(children) < 5000
    library = _native.Library(SESSION.view.path)
    assert sorted(library.world_indices) == sorted(SESSION.view.world_indices)
    assert all(library.world_info(c).parent_world == world for c in children)
    assert bpy.ops.mwb.sample.poll()
