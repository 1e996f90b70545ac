"""Sampling through the Sample operator: the engine runs as a child process, worlds stream into the
open library and the world list, cancel keeps what finished, and a second press adds worlds."""
import os

import bpy
import numpy as np
import pytest

from conftest import cancel_after_finished, drop_scene, sample_and_wait, save_blend

from many_worlds import _native
from many_worlds.core.session import SESSION


def test_sample_writes_a_library_next_to_the_blend_and_lists_its_worlds(tmp_path):
    _, boxes = drop_scene(bodies=2)
    save_blend(tmp_path)
    session = sample_and_wait(4, threads=2, seed=7)
    library_path = str(tmp_path / "shot.mwb")
    assert os.path.isfile(library_path)
    assert os.path.isfile(str(tmp_path / "shot.scene.json"))
    assert session.last_error == ""
    assert session.view is not None and sorted(session.view.world_indices) == [0, 1, 2, 3]
    # The list shows worlds in the order they finished (the file's order).
    assert [w.world_index for w in bpy.context.scene.mwb.worlds] == session.view.world_indices

    # Read back independently of the add-on: the boxes fell from where the scene put them.
    library = _native.Library(library_path)
    assert library.header["base_seed"] == 7
    names = [b for b in _native.Scene.from_json(library.header["scene_json"]).body_names]
    for box in boxes:
        i = names.index(box.name)
        for w in library.world_indices:
            positions = library.positions(w)
            start, end = positions[i, 0], positions[i, -1]
            assert np.allclose(start[:2], box.location[:2], atol=0.1 + 1e-3)
            assert box.location.z - 1e-3 <= start[2] <= box.location.z + 0.1 + 1e-3
            assert end[2] < 0.2, "the box should lie on the ground at the end"
    # Variation makes the worlds differ.
    assert not np.allclose(library.positions(0)[:, 0], library.positions(1)[:, 0])


def test_sampling_again_adds_the_next_worlds(tmp_path):
    drop_scene(bodies=1)
    save_blend(tmp_path)
    sample_and_wait(3)
    sample_and_wait(2)
    assert sorted(SESSION.view.world_indices) == [0, 1, 2, 3, 4]
    assert len(bpy.context.scene.mwb.worlds) == 5
    assert sorted(_native.Library(str(tmp_path / "shot.mwb")).world_indices) == [0, 1, 2, 3, 4]


def test_cancel_stops_the_engine_and_keeps_finished_worlds(tmp_path):
    drop_scene(bodies=2, frame_end=240)
    save_blend(tmp_path)
    mwb = bpy.context.scene.mwb
    mwb.world_count, mwb.threads, mwb.stop_at_rest = 5000, 1, False
    assert bpy.ops.mwb.sample() == {"FINISHED"}
    cancel_after_finished(2)
    assert SESSION.engine is None and SESSION.last_error == ""
    kept = SESSION.view.world_indices
    assert 2 <= len(kept) < 5000
    assert "cancelled" in SESSION.status
    assert len(_native.Library(str(tmp_path / "shot.mwb")).world_indices) == len(kept)


def test_engine_failure_is_reported(tmp_path):
    _, boxes = drop_scene(bodies=1)
    save_blend(tmp_path)
    sample_and_wait(1)
    # The library belongs to the scene it was sampled from; an edited scene cannot append to it.
    boxes[0].location.x += 1
    bpy.context.view_layer.update()
    sample_and_wait(1)
    assert SESSION.last_error, SESSION.status
    assert "another run" in SESSION.last_error
    assert "failed" in SESSION.status
    assert SESSION.view.world_indices == [0]


def test_an_unsampleable_scene_is_refused_before_the_engine_starts(tmp_path):
    drop_scene(bodies=1)
    save_blend(tmp_path)
    bpy.data.objects["Box0"].rigid_body.mass = 0.0
    bpy.data.objects["Box0"].rigid_body.collision_shape = "MESH"
    with pytest.raises(RuntimeError, match="mass_kg must be > 0"):
        bpy.ops.mwb.sample()
    assert SESSION.engine is None
    assert not os.path.exists(str(tmp_path / "shot.mwb"))
