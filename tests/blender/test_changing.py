"""Adding objects to and removing them from sampled worlds through the add-on, with real engine runs.

Add Selected to Worlds: a ball placed after sampling above a standing domino makes children in
which the ball exists from the start and knocks the domino over, while a box far away replays the
parent bit for bit. Remove from Worlds: without the lower box of a stack the upper one ends a box
height lower in every child; the removed body is absent from the children (NaN rows), never drawn,
keyed, posed or matched by a box; an object deleted from the scene after sampling is removed too.
"""
import os
import time

import bpy
import numpy as np
import pytest

from conftest import add_rigid_body, cancel_after_finished, mesh_object, sample_and_wait, save_blend
from test_queries import PROJECTION, SIZE, VIEW, add_box, matching_worlds, to_screen
from test_refining import pump, select_only

from many_worlds import compat, scene_boxes
from many_worlds.core import path_budget, paths
from many_worlds.core import family as core_family
from many_worlds.core.session import SESSION
from many_worlds.draw import paths as path_overlay
from many_worlds.operators import changing

FRAME_END = 49
BOX_HALF_M = 0.1
# Above the domino's top edge (it is 4 cm thick): the ball hits the edge and pushes it over.
BALL_START = (0.04, 0, 1.0)


def set_frame_range(frame_end=FRAME_END):
    scene = bpy.context.scene
    scene.rigidbody_world.point_cache.frame_start = 1
    scene.rigidbody_world.point_cache.frame_end = frame_end
    scene.frame_start, scene.frame_end = 1, frame_end


def ground():
    add_rigid_body(mesh_object("Ground", location=(0, 0, -0.5), scale=(5, 5, 0.5)), "PASSIVE")


def box(name, location, scale=(BOX_HALF_M,) * 3):
    return add_rigid_body(mesh_object(name, location=location, scale=scale), "ACTIVE", mass=0.5)


def body(name):
    return SESSION.view.body_names.index(name)


def final_position(world, name):
    return SESSION.view.library.positions(world)[body(name), -1]


def drawn_as_selected(world):
    """(the bodies whose paths are drawn, their line-list vertices) of `world` selected, as the
    viewport's paths overlay prepares them."""
    bpy.ops.mwb.select_world(world=world)
    overlay = path_overlay.OVERLAY
    overlay.update(bpy.context)
    selected, bodies, _ = overlay.arrays.drawn[0]
    assert selected == world
    return bodies, overlay.arrays.selected


def run_operator(operator, world, count=3):
    """Select `world`, press the operator (the real engine child) and pump the poller to its end.
    Returns the new worlds."""
    bpy.ops.mwb.select_world(world=world)
    bpy.context.scene.mwb.refine_count = count
    before = set(SESSION.view.world_indices)
    assert operator() == {"FINISHED"}
    assert SESSION.run is not None
    pump()
    assert SESSION.last_error == "", SESSION.status
    return sorted(set(SESSION.view.world_indices) - before)


# --- adding ---------------------------------------------------------------------------------------

@pytest.fixture
def domino_scene(tmp_path):
    """A standing domino and a box far from it, at rest on the ground from the start; sampled."""
    ground()
    box("Domino", (0, 0, 0.2), scale=(0.02, 0.1, 0.2))
    box("Far", (2, 0, BOX_HALF_M))
    set_frame_range()
    save_blend(tmp_path)
    sample_and_wait(2, threads=2, stop_at_rest=False)
    return tmp_path


def add_ball():
    """A heavy ball above the domino's top edge, placed after sampling."""
    ball = mesh_object("Ball", "uv_sphere", location=BALL_START, scale=(0.05,) * 3)
    return add_rigid_body(ball, "ACTIVE", shape="SPHERE", mass=1.0)


def test_an_added_ball_exists_in_the_children_and_only_what_it_touches_changes(domino_scene):
    view = SESSION.view
    parent = view.world_indices[0]
    sampled_json = paths.scene_json_path(view.path)
    with open(sampled_json) as f:
        sampled_scene = f.read()
    add_ball()
    select_only("Ball")
    children = run_operator(bpy.ops.mwb.add_to_worlds, parent)
    assert len(children) == 3 and "Added into 3 new worlds" in SESSION.status
    view = SESSION.view
    library = view.library
    # The library's current scene has the ball appended; the header keeps the scene as sampled.
    assert view.body_names == ["Domino", "Far", "Ground", "Ball"] and library.body_count == 4
    assert "Ball" not in library.header.scene_json
    # The sampled scene's file is untouched; the ball was exported to a file of its own.
    with open(sampled_json) as f:
        assert f.read() == sampled_scene
    with open(paths.added_scene_json_path(view.path)) as f:
        assert '"Ball"' in f.read()
    ball, far, domino = body("Ball"), body("Far"), body("Domino")
    assert not view.present(parent)[ball] and np.isnan(library.positions(parent)[ball]).all()
    parent_positions = library.positions(parent)
    parent_orientations = library.orientations(parent)
    for child in children:
        assert view.present(child).all()
        positions = library.positions(child)
        assert np.isfinite(positions[ball]).all()
        # The ball falls from where it was placed.
        assert np.allclose(positions[ball, 0], BALL_START, atol=2e-3)
        assert positions[ball, -1, 2] < 0.5
        frames = min(positions.shape[1], parent_positions.shape[1])
        # Nothing touched the far box: it replays the parent bit for bit.
        np.testing.assert_array_equal(positions[far, :frames], parent_positions[far, :frames])
        np.testing.assert_array_equal(library.orientations(child)[far, :frames], parent_orientations[far, :frames])
        # The ball knocked the domino over.
        tilt = 2 * np.degrees(np.arccos(min(1.0, abs(float(np.dot(library.orientations(child)[domino, -1],
                                                                        parent_orientations[domino, -1]))))))
        assert tilt > 30, tilt
        line = view.lineages()[child]
        assert line.parent == parent and line.added == (ball,) and line.removed == ()
        assert core_family.relation_text(line, view.body_names) == f"child of {parent}: +Ball"
    # The children are listed and indexed with the ball's path.
    assert [w.world_index for w in bpy.context.scene.mwb.worlds] == view.world_indices
    lq = scene_boxes.library_query()
    lq.sync()
    assert lq.index.world_count == len(view.world_indices)
    # Selected, a child is drawn with the ball's path, the parent without it.
    bodies, segments = drawn_as_selected(children[0])
    assert ball in bodies and len(segments) and np.isfinite(segments).all()
    assert ball not in drawn_as_selected(parent)[0]


def test_previewing_a_world_without_the_ball_leaves_it_where_it_is_drawn_as_wire(domino_scene):
    parent = SESSION.view.world_indices[0]
    ball = add_ball()
    select_only("Ball")
    child = run_operator(bpy.ops.mwb.add_to_worlds, parent, count=1)[0]
    scene = bpy.context.scene
    scene.frame_set(30)
    own = ball.matrix_world.translation.copy()
    bpy.ops.mwb.select_world(world=parent)
    assert ball.display_type == "WIRE" and np.allclose(ball.matrix_world.translation, own)
    # Still selectable: absent objects can be picked to add them.
    assert ball.select_get()
    bpy.ops.mwb.select_world(world=child)
    assert ball.display_type == "TEXTURED"
    positions, hz = SESSION.view.library.positions(child), SESSION.view.record_hz(child)
    frame = round((30 - 1) / 24 * hz)
    assert np.allclose(ball.matrix_world.translation, positions[body("Ball"), frame], atol=2e-3)
    bpy.ops.mwb.select_world(world=parent)
    assert ball.display_type == "WIRE" and np.allclose(ball.matrix_world.translation, own)
    assert bpy.ops.mwb.end_preview() == {"FINISHED"}
    assert ball.display_type == "TEXTURED" and np.allclose(ball.matrix_world.translation, own)


def test_add_refuses_bad_selections_with_one_line_errors(domino_scene):
    world = SESSION.view.world_indices[0]
    bpy.ops.mwb.select_world(world=world)
    for ob in bpy.context.view_layer.objects:
        ob.select_set(False)
    with pytest.raises(RuntimeError, match="Select the objects to add"):
        bpy.ops.mwb.add_to_worlds()
    mesh_object("Decoration", location=(1, 1, 1))
    select_only("Decoration")
    with pytest.raises(RuntimeError, match="Decoration has no rigid body"):
        bpy.ops.mwb.add_to_worlds()
    select_only("Domino")
    with pytest.raises(RuntimeError, match=f"Domino is already in world {world}"):
        bpy.ops.mwb.add_to_worlds()
    select_only("Decoration")
    with pytest.raises(RuntimeError, match=f"None of the selected objects is in world {world}"):
        bpy.ops.mwb.remove_from_worlds()
    # A body not in the selected world cannot be refined there either.
    add_ball()
    select_only("Ball")
    child = run_operator(bpy.ops.mwb.add_to_worlds, world, count=1)[0]
    bpy.ops.mwb.select_world(world=world)
    select_only("Ball")
    with pytest.raises(RuntimeError, match="Select the objects to refine"):
        bpy.ops.mwb.refine(rect=(0, 0, SIZE[0], SIZE[1]), view_matrix=VIEW.ravel().tolist(),
                           projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE)
    assert child in SESSION.view.world_indices and SESSION.run is None


def test_an_object_moved_after_sampling_is_updated_as_a_body_of_its_own(domino_scene):
    first, second = SESSION.view.world_indices[:2]
    ball = add_ball()
    select_only("Ball")
    with_ball = run_operator(bpy.ops.mwb.add_to_worlds, first, count=1)[0]
    # The same ball, unchanged, joins another world as the same body.
    run_operator(bpy.ops.mwb.add_to_worlds, second, count=1)
    assert SESSION.view.body_names.count("Ball") == 1
    # Moved, then updated in a world that has it: the world's ball starts where it is now, as a
    # second body standing for the same object; the world it came from keeps the old one.
    ball.location.x += 0.5
    moved_start = (BALL_START[0] + 0.5, BALL_START[1], BALL_START[2])
    updated = run_operator(bpy.ops.mwb.update_in_worlds, with_ball, count=1)[0]
    assert "Updated in 1 new worlds" in SESSION.status
    view = SESSION.view
    old, new = [i for i, name in enumerate(view.body_names) if name == "Ball"]
    assert view.present(updated)[new] and not view.present(updated)[old]
    assert view.present(with_ball)[old] and not view.present(with_ball)[new]
    assert np.allclose(view.library.positions(updated)[new, 0], moved_start, atol=2e-3)
    assert core_family.relation_text(view.lineages()[updated], view.body_names) == f"child of {with_ball}: ~Ball"
    # Preview and bake follow the body each world has.
    bpy.context.scene.frame_set(1)
    bpy.ops.mwb.select_world(world=updated)
    assert ball.display_type == "TEXTURED" and np.allclose(ball.matrix_world.translation, moved_start, atol=2e-3)
    bpy.ops.mwb.select_world(world=with_ball)
    assert np.allclose(ball.matrix_world.translation, BALL_START, atol=2e-3)
    # Queries and rankings name the object: either of its bodies, whichever a world has.
    assert set(scene_boxes.body_indices(["Ball"], view)) == {old, new}
    # Updating it again, unchanged, is refused by the engine with the reason.
    bpy.ops.mwb.select_world(world=updated)
    bpy.context.scene.mwb.refine_count = 1
    select_only("Ball")
    assert bpy.ops.mwb.update_in_worlds() == {"FINISHED"}
    pump()
    assert "'Ball' is unchanged" in SESSION.last_error and "Updating failed" in SESSION.status
    # An object the world lacks is added, not updated.
    bpy.ops.mwb.select_world(world=first)
    select_only("Ball")
    with pytest.raises(RuntimeError, match=f"Ball is not in world {first}; add it instead"):
        bpy.ops.mwb.update_in_worlds()
    assert SESSION.run is None
    # Baking the updated world keys the ball from its new body and never hides it.
    bpy.ops.mwb.select_world(world=updated)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    assert compat.find_fcurve(ball, "location", 0).evaluate(1) == pytest.approx(moved_start[0], abs=2e-3)
    assert compat.find_fcurve(ball, "hide_render", 0) is None, "a world with the ball never hides it"


def test_add_and_remove_wait_for_a_running_engine_and_need_a_library(domino_scene):
    mwb = bpy.context.scene.mwb
    bpy.ops.mwb.select_world(world=SESSION.view.world_indices[0])
    add_ball()
    select_only("Ball")
    mwb.world_count, mwb.threads = 2000, 1
    assert bpy.ops.mwb.sample() == {"FINISHED"}
    assert not bpy.ops.mwb.add_to_worlds.poll() and not bpy.ops.mwb.remove_from_worlds.poll()
    assert changing.bodies_to_add(bpy.context)[1] == "Sampling is running; wait for it or cancel it first"
    bpy.ops.mwb.cancel_sampling()
    pump()
    assert bpy.ops.mwb.add_to_worlds.poll()
    SESSION.close()
    with pytest.raises(RuntimeError, match="Open or sample a library first"):
        bpy.ops.mwb.add_to_worlds()


# --- removing -------------------------------------------------------------------------------------

@pytest.fixture
def stack_scene(tmp_path):
    """Two boxes stacked on the ground, at rest from the start; sampled."""
    ground()
    box("Lower", (0, 0, BOX_HALF_M))
    box("Upper", (0, 0, 3 * BOX_HALF_M))
    set_frame_range()
    save_blend(tmp_path)
    sample_and_wait(2, threads=2, stop_at_rest=False)
    return tmp_path


def check_upper_fell(parents, children):
    """The upper box ends a box height lower without the lower one, and the lower one is absent."""
    view = SESSION.view
    lower, upper = body("Lower"), body("Upper")
    drop = final_position(parents[0], "Upper")[2] - 2 * BOX_HALF_M
    for child in children:
        assert not view.present(child)[lower] and view.present(child)[upper]
        assert np.isnan(view.library.positions(child)[lower]).all()
        assert np.isnan(view.library.orientations(child)[lower]).all()
        assert abs(final_position(child, "Upper")[2] - drop) < 0.02, final_position(child, "Upper")
        assert view.lineages()[child].removed == (lower,)


def test_removing_the_lower_box_drops_the_upper_one_and_the_lower_is_gone(stack_scene):
    view = SESSION.view
    parents = list(view.world_indices)
    select_only("Lower")
    children = run_operator(bpy.ops.mwb.remove_from_worlds, parents[0])
    assert len(children) == 3 and "Removed from 3 new worlds" in SESSION.status
    check_upper_fell(parents, children)
    lower, upper = body("Lower"), body("Upper")
    assert core_family.relation_text(view.lineages()[children[0]], view.body_names).endswith(": -Lower")
    # Not drawn: selected, the child shows the upper box's path alone.
    bodies, segments = drawn_as_selected(children[0])
    assert lower not in bodies and upper in bodies
    expected = path_budget.line_segments(view.library.polyline(children[0]), bodies, 1)
    assert np.isfinite(segments).all() and np.array_equal(segments, expected)
    # The world list sums only bodies the world has.
    summary = view.world_summary(children[0])
    assert np.isfinite(summary["travel_m"]) and summary["travel_m"] > 0.15


def test_a_box_on_a_removed_body_never_matches_the_worlds_without_it(stack_scene):
    view = SESSION.view
    parents = list(view.world_indices)
    select_only("Lower")
    children = run_operator(bpy.ops.mwb.remove_from_worlds, parents[0])
    x, y = to_screen(final_position(parents[0], "Lower")[None])[0]
    rect = (x - 15, y - 15, x + 15, y + 15)
    box_on_lower = add_box(rect, bodies="Lower")
    assert matching_worlds() == set(parents)
    box_on_lower.negative = True
    assert matching_worlds() == set(children)
    # The upper box ends where the lower one was in the children: a box on either body matches all.
    box_on_lower.negative = False
    bpy.ops.mwb.clear_boxes()
    add_box(rect, bodies="Lower,Upper")
    assert matching_worlds() == set(parents) | set(children)
    bpy.ops.mwb.clear_boxes()
    # Ranking over the lower box lists only the worlds it is in.
    ids, values = scene_boxes.library_query().rank("path_length_m", [body("Lower")])
    assert sorted(ids.tolist()) == sorted(parents) and np.isfinite(values).all()
    ids, values = scene_boxes.library_query().rank("orientation_to_goal_rad", [body("Lower"), body("Upper")])
    assert sorted(ids.tolist()) == sorted(parents + children) and np.isfinite(values).all()


def test_bake_and_preview_of_a_world_without_the_lower_box(stack_scene):
    parent = SESSION.view.world_indices[0]
    lower, upper = bpy.data.objects["Lower"], bpy.data.objects["Upper"]
    own = lower.matrix_world.copy()
    select_only("Lower")
    child = run_operator(bpy.ops.mwb.remove_from_worlds, parent, count=1)[0]
    scene = bpy.context.scene
    scene.frame_set(40)
    # Still previewing the parent, which poses the lower box; the child puts it back where it was.
    bpy.ops.mwb.select_world(world=child)
    assert lower.display_type == "WIRE" and np.allclose(np.array(lower.matrix_world), np.array(own))
    assert upper.matrix_world.translation.z < 0.15
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    # The upper box is keyed; the lower one is not, it is keyed hidden from the first frame on.
    upper_paths = {f.data_path for f in compat.object_fcurves(upper)}
    assert upper_paths == {"location", "rotation_quaternion"} and upper.rigid_body.kinematic
    lower_paths = {f.data_path for f in compat.object_fcurves(lower)}
    assert lower_paths == {"hide_viewport", "hide_render"} and lower.rigid_body.kinematic
    assert lower.display_type == "TEXTURED"
    scene.frame_set(0)
    assert not lower.hide_viewport and not lower.hide_render
    for frame in (1, 20, FRAME_END + 10):
        scene.frame_set(frame)
        assert lower.hide_viewport and lower.hide_render
    scene.frame_set(FRAME_END)
    assert abs(upper.matrix_world.translation.z - BOX_HALF_M) < 0.02
    # Baking a world that has the lower box keys it again and drops the hide keys.
    bpy.ops.mwb.select_world(world=parent)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    assert {f.data_path for f in compat.object_fcurves(lower)} == {"location", "rotation_quaternion"}
    scene.frame_set(20)
    assert not lower.hide_viewport and not lower.hide_render
    assert lower.matrix_world.translation.z < 0.15


def test_an_object_deleted_after_sampling_is_removed_from_the_worlds(stack_scene):
    view = SESSION.view
    parents = list(view.world_indices)
    bpy.data.objects.remove(bpy.data.objects["Lower"])
    for ob in bpy.context.scene.objects:
        ob.select_set(False)
    children = run_operator(bpy.ops.mwb.remove_from_worlds, parents[1], count=2)
    assert len(children) == 2
    check_upper_fell(parents, children)
    # The list and the paths of every world still work without the object.
    assert [w.world_index for w in bpy.context.scene.mwb.worlds] == view.world_indices
    bpy.context.scene.frame_set(FRAME_END)
    assert bpy.ops.mwb.select_world(world=children[0]) == {"FINISHED"}
    assert bpy.data.objects["Upper"].matrix_world.translation.z < 0.25


def test_cancel_keeps_the_finished_worlds_of_a_removal(tmp_path):
    ground()
    box("Lower", (0, 0, BOX_HALF_M))
    box("Upper", (0, 0, 3 * BOX_HALF_M))
    set_frame_range(240)
    save_blend(tmp_path)
    sample_and_wait(1, threads=1, stop_at_rest=False)
    world = SESSION.view.world_indices[0]
    bpy.ops.mwb.select_world(world=world)
    select_only("Lower")
    mwb = bpy.context.scene.mwb
    mwb.refine_count, mwb.threads = 5000, 1
    assert bpy.ops.mwb.remove_from_worlds() == {"FINISHED"}
    assert SESSION.runs[-1].label == "Removing" and not bpy.ops.mwb.sample.poll()
    cancel_after_finished(2)
    assert SESSION.run is None and SESSION.last_error == ""
    assert "Removing cancelled" in SESSION.status
    children = [w for w in SESSION.view.world_indices if w != world]
    assert 2 <= len(children) < 5000
    assert all(not SESSION.view.present(c)[body("Lower")] for c in children)
    assert os.path.isfile(SESSION.view.path)
