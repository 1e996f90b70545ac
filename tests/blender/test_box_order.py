"""Ordered boxes in the add-on: a box met after another one. Boxes dropped from 1 m pass a box
around where they start before a box around where they rest, so "rest after start" keeps the worlds
meeting both and "start after rest" keeps none; the add-on's matches equal a direct PathIndex
query with the same order; a disabled or deleted predecessor leaves its follower unordered; the
list offers no order that closes a cycle; the order is saved with the .blend."""
import bpy
import pytest

from camera_math import look_at, screen_of
from conftest import drop_scene, sample_and_wait, save_blend
from test_queries import PROJECTION, SIZE, matching_worlds

from many_worlds import _native
from many_worlds.core.session import SESSION

# From the side, so a fall is a long way down the screen.
VIEW = look_at([0.3, -4.0, 0.6], [0.3, 0.0, 0.5])


def add_box(rect):
    assert bpy.ops.mwb.add_box(rect=rect, view_matrix=VIEW.ravel().tolist(),
                               projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE,
                               bodies="Box0") == {"FINISHED"}
    return bpy.context.scene.mwb.boxes[-1]


def rect_at(world, frame, half_px):
    """A screen rectangle around where Box0 is at recorded `frame` of `world`."""
    view = SESSION.view
    x, y = screen_of(VIEW, PROJECTION, SIZE, view.library.positions(world)[view.body_names.index("Box0"), frame])
    return (x - half_px, y - half_px, x + half_px, y + half_px)


def direct_matches(rects_and_afters):
    """Box0 boxes (rect, after) queried on a PathIndex built here from the library file itself."""
    library = _native.Library(SESSION.view.path)
    scene = _native.Scene.from_json(library.header.scene_json)
    index = _native.PathIndex(_native.body_bounding_radii(scene))
    index.add_library(library)
    box0 = scene.body_names.index("Box0")
    boxes = [_native.QueryBox(VIEW, PROJECTION, SIZE, rect, bodies=[box0], after=after)
             for rect, after in rects_and_afters]
    return {int(w) for w in index.query(boxes).matching}


@pytest.fixture
def start_and_rest(tmp_path):
    """A sampled library and two boxes over Box0: box 1 where it starts, box 2 where it rests in one world."""
    drop_scene(bodies=2)
    save_blend(tmp_path)
    sample_and_wait(24, threads=2, seed=3)
    worlds = sorted(SESSION.view.world_indices)
    start = add_box(rect_at(worlds[0], 0, 60))
    rest = add_box(rect_at(worlds[5], -1, 15))
    return start, rest


def test_a_box_met_after_another_keeps_the_worlds_meeting_them_in_that_order(start_and_rest):
    start, rest = start_and_rest
    both = matching_worlds()
    assert both and len(both) < len(SESSION.view.world_indices), "the rest box should split the worlds"
    rest.after = "0"
    assert rest.after_box == 0
    assert matching_worlds() == both == direct_matches([(tuple(start.rect), -1), (tuple(rest.rect), 0)])
    # The other way round: nothing rises back to where it started after resting.
    rest.after = "NONE"
    start.after = "1"
    assert matching_worlds() == set() == direct_matches([(tuple(start.rect), 1), (tuple(rest.rect), -1)])
    # A disabled predecessor leaves the box unordered: the rest box alone.
    rest.enabled = False
    assert matching_worlds() == set(SESSION.view.world_indices)
    rest.enabled = True
    start.enabled = False
    rest_alone = matching_worlds()
    assert rest_alone == direct_matches([(tuple(rest.rect), -1)]) and both <= rest_alone


def after_choices(box):
    """The After menu of a box as the panel lists it."""
    from many_worlds import props
    return [name for _, name, *_ in props._after_items(box, bpy.context)]


def test_the_list_offers_no_order_that_closes_a_cycle_and_deleting_keeps_the_rest(start_and_rest, tmp_path):
    start, rest = start_and_rest
    third = add_box(tuple(rest.rect))
    rest.after = "0"
    third.after = "1"
    # Box 1 cannot come after box 2 or 3 (both come after it), nor after itself.
    assert after_choices(start) == ["None"]
    assert after_choices(third) == ["None", "Box 1", "Box 2"]
    with pytest.raises(TypeError):
        start.after = "2"
    assert start.after_box == -1
    assert [b.after_box for b in bpy.context.scene.mwb.boxes] == [-1, 0, 1]

    # Saved with the .blend.
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "shot.blend"))
    boxes = bpy.context.scene.mwb.boxes
    assert [b.after_box for b in boxes] == [-1, 0, 1] and boxes[2].after == "1"

    # Deleting box 2: box 3 (after it) is unordered and becomes box 2; deleting box 1 unorders the rest.
    assert bpy.ops.mwb.remove_box(index=1) == {"FINISHED"}
    assert [b.after_box for b in boxes] == [-1, -1]
    boxes[1].after = "0"
    assert bpy.ops.mwb.remove_box(index=0) == {"FINISHED"}
    assert [b.after_box for b in boxes] == [-1]
    assert matching_worlds() == direct_matches([(tuple(boxes[0].rect), -1)])

