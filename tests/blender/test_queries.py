"""Query boxes and ranking through the add-on's operators and properties, on worlds the engine
sampled: the add-on's matches equal a direct PathIndex query and a brute-force check on decoded
paths; boxes combine by AND; rankings follow the library's metric values; boxes and ranking
settings survive save and reload."""

import bpy
import numpy as np
import pytest

from camera_math import look_at, perspective
from conftest import drop_scene, sample_and_wait, save_blend

from many_worlds import _native, scene_boxes
from many_worlds.operators import seeking
from many_worlds.core.session import SESSION

SIZE = (1600, 1000)
VIEW = look_at([0.3, -1.0, 2.5], [0.3, 0.0, 0.05])
PROJECTION = perspective(0.8, SIZE[0] / SIZE[1], 0.1, 100)


def to_screen(points):
    """(n, 3) world points -> (n, 2) region pixels of the test camera."""
    homogeneous = np.c_[points, np.ones(len(points))] @ (PROJECTION @ VIEW).T
    ndc = homogeneous[:, :2] / homogeneous[:, 3:4]
    return (ndc + 1) / 2 * np.array(SIZE)


def add_box(rect, negative=False, bodies="Box0,Box1"):
    assert bpy.ops.mwb.add_box(rect=rect, view_matrix=VIEW.ravel().tolist(),
                               projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE,
                               negative=negative, bodies=bodies) == {"FINISHED"}
    return bpy.context.scene.mwb.boxes[-1]


def matching_worlds():
    view = SESSION.view
    return {w for w, m in zip(view.world_indices, view.matching) if m}


def direct_matches(boxes):
    """The same boxes queried on a PathIndex built here from the library file itself."""
    library = _native.Library(SESSION.view.path)
    scene = _native.Scene.from_json(library.header.scene_json)
    index = _native.PathIndex(_native.body_bounding_radii(scene))
    index.add_library(library)
    native_boxes = [_native.QueryBox(VIEW, PROJECTION, SIZE, rect, negative=negative,
                                     bodies=[scene.body_names.index(n) for n in names], time_window=window)
                    for rect, negative, names, window in boxes]
    result = index.query(native_boxes)
    return {int(w) for w in result.matching}, result


def end_rect(world, body="Box0", half_px=20):
    """A screen rectangle around where `body` ends in `world`."""
    i = SESSION.view.body_names.index(body)
    x, y = to_screen(SESSION.view.library.positions(world)[i, -1:])[0]
    return (x - half_px, y - half_px, x + half_px, y + half_px)


@pytest.fixture
def sampled(tmp_path):
    drop_scene(bodies=2)
    save_blend(tmp_path)
    sample_and_wait(24, threads=2, seed=3)
    assert len(SESSION.view.world_indices) == 24
    return SESSION.view


def test_a_box_matches_a_direct_index_query_and_the_decoded_paths(sampled):
    view = sampled
    world = sorted(view.world_indices)[5]
    rect = end_rect(world)
    add_box(rect)
    ours = matching_worlds()
    direct, result = direct_matches([(rect, False, ["Box0", "Box1"], None)])
    assert ours == direct
    assert world in ours and 0 < len(ours) < len(view.world_indices), "the box should split the worlds"
    # The index answers in world order, the view in file order: the mapping must not mix worlds up.
    lq = scene_boxes.library_query()
    for w, satisfied in zip(result.world_indices, result.boxes_satisfied):
        assert lq.result.boxes_satisfied[view.world_indices.index(int(w))] == satisfied

    # Brute force on the decoded paths (full rate): a point well inside means a match, a world
    # with no point near the rectangle cannot match (polyline chords vs points, codec error).
    x0, y0, x1, y1 = rect
    bodies = [view.body_names.index("Box0"), view.body_names.index("Box1")]
    for w in view.world_indices:
        screen = to_screen(view.library.positions(w)[bodies].reshape(-1, 3))

        def inside(margin):
            return np.any((screen[:, 0] > x0 - margin) & (screen[:, 0] < x1 + margin)
                          & (screen[:, 1] > y0 - margin) & (screen[:, 1] < y1 + margin))
        if inside(-3):
            assert w in ours, f"world {w} has a path point inside the box"
        if not inside(15):
            assert w not in ours, f"world {w} has no path point near the box"


def test_time_windowed_box_matches_the_direct_query(sampled):
    rect = end_rect(sorted(sampled.world_indices)[2], half_px=60)
    box = add_box(rect)
    everywhere = matching_worlds()
    box.use_time_window, box.time_start_s, box.time_end_s = True, 0.0, 0.3
    early = matching_worlds()
    assert early == direct_matches([(rect, False, ["Box0", "Box1"], (0.0, 0.3))])[0]
    # Early in the drop most boxes are still in the air above their resting spots.
    assert early < everywhere
    box.time_start_s, box.time_end_s = 0.3, 10.0
    assert matching_worlds() == direct_matches([(rect, False, ["Box0", "Box1"], (0.3, 10.0))])[0]


def test_a_window_that_ends_before_it_starts_is_named_not_mended(sampled):
    worlds = sorted(sampled.world_indices)
    scene = bpy.context.scene
    first = add_box(end_rect(worlds[2], half_px=60))
    first.enabled = False
    box = add_box(end_rect(worlds[3], half_px=60))
    box.use_time_window, box.time_start_s, box.time_end_s = True, 2.0, 3.0
    assert SESSION.goal_problem == ""
    box.time_end_s = 1.0
    # Passed on as set; the module's refusal names the box as the list does, and the panel and
    # Seek say it. Meanwhile no part filters the worlds.
    assert scene_boxes.spec_of(box, sampled).time_window == (2.0, 1.0)
    assert SESSION.goal_problem == "Box 2 has a time window (time_window) that ends before it starts"
    assert seeking.seek_problem(scene) == SESSION.goal_problem
    assert matching_worlds() == set(worlds)
    box.time_end_s = 2.5
    assert SESSION.goal_problem == "" and seeking.seek_problem(scene) == ""
    rect = tuple(box.rect)
    assert matching_worlds() == direct_matches([(rect, False, ["Box0", "Box1"], (2.0, 2.5))])[0]
    # A pose part's window alike.
    pose = scene_boxes.store_pose(scene, ["Box0"])
    pose.time_start_s = pose.time_end_s + 1.0
    assert SESSION.goal_problem == "Pose 3 has a time window (time_window) that ends before it starts"
    pose.use_time_window = False
    assert SESSION.goal_problem == ""


def test_positive_and_negative_boxes_combine_by_and(sampled):
    view = sampled
    every = set(view.world_indices)
    worlds = sorted(every)
    keep_rect, reject_rect = end_rect(worlds[1], half_px=70), end_rect(worlds[6], "Box1", half_px=40)
    keep = direct_matches([(keep_rect, False, ["Box0"], None)])[0]
    near = direct_matches([(reject_rect, False, ["Box1"], None)])[0]
    assert keep and near

    add_box(keep_rect, bodies="Box0")
    assert matching_worlds() == keep
    reject = add_box(reject_rect, negative=True, bodies="Box1")
    assert matching_worlds() == keep - near
    reject.enabled = False
    assert matching_worlds() == keep
    reject.enabled = True
    reject.negative = False
    assert matching_worlds() == keep & near
    reject.negative = True
    assert bpy.ops.mwb.remove_box(index=0) == {"FINISHED"}
    assert matching_worlds() == every - near
    assert bpy.ops.mwb.clear_boxes() == {"FINISHED"}
    assert matching_worlds() == every


def library_metric(world, name, bodies, combine):
    values = [SESSION.view.library.metrics(world)[name][i] for i in bodies]
    return sum(values) if combine == "SUM" else max(values)


@pytest.mark.parametrize("metric,combine,descending", [("path_length_m", "SUM", False),
                                                       ("collision_count", "MAX", True),
                                                       ("angular_travel_rad", "SUM", True)])
def test_ranking_follows_the_library_metric_over_the_matching_worlds(sampled, metric, combine, descending):
    view = sampled
    add_box(end_rect(sorted(view.world_indices)[3], half_px=25))
    matching = matching_worlds()
    assert 1 < len(matching) < len(view.world_indices)
    settings = bpy.context.scene.mwb
    settings.rank_metric, settings.rank_combine, settings.rank_descending = metric, combine, descending
    settings.rank_bodies = "SIMULATED"
    ranking = scene_boxes.RANKING.get(bpy.context)
    bodies = view.simulated_bodies()
    expected_values = {w: library_metric(w, metric, bodies, combine) for w in matching}
    assert set(ranking.ids.tolist()) == matching
    np.testing.assert_allclose(ranking.values, [expected_values[int(w)] for w in ranking.ids])
    assert list(ranking.values) == sorted(ranking.values, reverse=descending)


def test_boxes_met_lists_every_world_with_its_count(sampled):
    view = sampled
    worlds = sorted(view.world_indices)
    rects = [end_rect(worlds[k], half_px=60) for k in (0, 4, 8)]
    for rect in rects:
        add_box(rect)
    per_box = [direct_matches([(rect, False, ["Box0", "Box1"], None)])[0] for rect in rects]
    settings = bpy.context.scene.mwb
    settings.rank_metric, settings.rank_descending = "boxes_met", True
    ranking = scene_boxes.RANKING.get(bpy.context)
    assert sorted(ranking.ids.tolist()) == worlds, "every world is listed, not only the matching ones"
    for w, value in zip(ranking.ids, ranking.values):
        assert value == sum(int(w) in matches for matches in per_box)
    assert list(ranking.values) == sorted(ranking.values, reverse=True)
    # Files saved when the metric was called "constraints_satisfied" hold its position, 6: still boxes_met.
    settings["rank_metric"] = 6
    assert settings.rank_metric == "boxes_met"


def test_boxes_and_ranking_settings_survive_save_and_reload(sampled, tmp_path):
    view = sampled
    keep_rect = end_rect(sorted(view.world_indices)[2], half_px=80)
    add_box(keep_rect)
    box = add_box(end_rect(sorted(view.world_indices)[9], half_px=30), negative=True, bodies="Box1")
    box.use_time_window, box.time_start_s, box.time_end_s, box.swept = True, 0.5, 3.0, True
    settings = bpy.context.scene.mwb
    settings.rank_metric, settings.rank_combine, settings.rank_descending = "time_to_rest_s", "MAX", True
    bpy.data.objects["Box1"].select_set(True)
    bpy.context.view_layer.objects.active = bpy.data.objects["Box1"]
    with bpy.context.temp_override(selected_objects=[bpy.data.objects["Box1"]]):
        assert bpy.ops.mwb.rank_use_selected() == {"FINISHED"}
    before = matching_worlds()
    ranked_before = scene_boxes.RANKING.get(bpy.context).ids.tolist()
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    assert SESSION.view is None
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "shot.blend"))
    settings = bpy.context.scene.mwb
    assert len(settings.boxes) == 2
    loaded = settings.boxes[1]
    assert loaded.negative and loaded.swept and loaded.use_time_window
    assert (loaded.time_start_s, loaded.time_end_s) == (0.5, 3.0)
    assert [b.name for b in loaded.bodies] == ["Box1"]
    np.testing.assert_allclose(np.array(loaded.view_matrix).reshape(4, 4), VIEW, atol=1e-6)
    assert tuple(loaded.region_size) == SIZE
    assert (settings.rank_metric, settings.rank_combine, settings.rank_descending) == ("time_to_rest_s", "MAX", True)
    assert settings.rank_bodies == "LISTED" and [b.name for b in settings.rank_body_names] == ["Box1"]
    # The reopened library is queried with the saved boxes straight away.
    assert matching_worlds() == before
    assert scene_boxes.RANKING.get(bpy.context).ids.tolist() == ranked_before


def test_worlds_arriving_while_sampling_are_queried(sampled):
    rect = end_rect(sorted(sampled.world_indices)[0], half_px=50)
    add_box(rect)
    sample_and_wait(16)
    assert len(SESSION.view.world_indices) == 40
    assert scene_boxes.library_query().index.world_count == 40
    assert matching_worlds() == direct_matches([(rect, False, ["Box0", "Box1"], None)])[0]



def test_the_bodies_a_box_tests_are_the_engines_simulated_bodies_before_and_after_sampling(tmp_path):
    """Before a library exists the panel asks the engine's own rule (BodyRole); after sampling the
    library answers. Both must name the same bodies, including the cases Blender's raw flags get
    wrong: Dynamic off (stays put) and Animated keyed off (let go, then simulated)."""
    ground, (free, still, released) = drop_scene(bodies=3)
    still.rigid_body.enabled = False
    released.rigid_body.kinematic = True
    released.keyframe_insert("rigid_body.kinematic", frame=1)
    released.rigid_body.kinematic = False
    released.keyframe_insert("rigid_body.kinematic", frame=10)
    assert SESSION.view is None
    before = scene_boxes.simulated_body_names(bpy.context.scene)
    assert sorted(before) == sorted([free.name, released.name]), before
    save_blend(tmp_path)
    sample_and_wait(2)
    assert SESSION.view is not None and SESSION.last_error == "", SESSION.last_error
    after = scene_boxes.simulated_body_names(bpy.context.scene)
    assert sorted(after) == sorted(before)
    roles = dict(zip(SESSION.view.body_names, SESSION.view.scene.body_roles))
    assert roles[still.name] == _native.BodyRole.DISABLED and roles[ground.name] == _native.BodyRole.STATIC
