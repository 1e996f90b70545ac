"""Sampling through the Sample operator: the engine runs as a child process, worlds stream into the
open library and the world list, cancel keeps what finished, and a second press adds worlds."""
import fcntl
import json
import os
import re
import subprocess

import bpy
import numpy as np
import pytest

from conftest import cancel_after_finished, drop_scene, sample_and_wait, save_blend

import many_worlds
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
    assert library.header.base_seed == 7
    names = [b for b in _native.Scene.from_json(library.header.scene_json).body_names]
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


def sample_then_cancel(tmp_path, count):
    """Press Sample for `count` slow worlds (30 s each, one thread) and Cancel once two are stored.
    The boxes bounce without losing energy, so they never rest or sleep: every world takes its time."""
    ground, boxes = drop_scene(bodies=4, frame_end=720)
    for ob in [ground, *boxes]:
        ob.rigid_body.restitution = 1.0
        ob.rigid_body.linear_damping = ob.rigid_body.angular_damping = 0.0
    save_blend(tmp_path)
    mwb = bpy.context.scene.mwb
    mwb.world_count, mwb.threads, mwb.stop_at_rest = count, 1, False
    assert bpy.ops.mwb.sample() == {"FINISHED"}
    cancel_after_finished(2)
    return mwb


def test_cancel_stops_the_engine_and_keeps_finished_worlds(tmp_path):
    sample_then_cancel(tmp_path, 5000)
    assert SESSION.run is None and SESSION.last_error == ""
    kept = SESSION.view.world_indices
    assert 2 <= len(kept) < 5000
    assert "cancelled" in SESSION.status
    assert len(_native.Library(str(tmp_path / "shot.mwb")).world_indices) == len(kept)


def test_engine_failure_is_reported(tmp_path):
    drop_scene(bodies=1)
    save_blend(tmp_path)
    sample_and_wait(1)
    # Another process holds the library's writer lock: the engine stops and says why.
    with open(tmp_path / "shot.mwb", "rb") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        sample_and_wait(1)
    assert SESSION.last_error, SESSION.status
    assert "another process is writing" in SESSION.last_error
    assert "failed" in SESSION.status
    assert SESSION.view.world_indices == [0]


def library_worlds(path):
    return sorted(_native.Library(str(path)).world_indices)


def test_a_changed_range_samples_into_a_new_library_and_the_old_one_stays(tmp_path):
    _, boxes = drop_scene(bodies=2)
    save_blend(tmp_path)
    settings = bpy.context.scene.mwb
    sample_and_wait(3)
    old_max = tuple(boxes[0].mwb_variation.location_max)
    boxes[0].mwb_variation.location_max = (0.3, 0.3, 0.3)
    sample_and_wait(2)
    assert SESSION.last_error == "", SESSION.last_error
    assert "shot-2.mwb" in SESSION.status and "shot.mwb" in SESSION.status
    assert SESSION.view.path == str(tmp_path / "shot-2.mwb") and settings.library_path == "//shot-2.mwb"
    assert library_worlds(tmp_path / "shot-2.mwb") == [0, 1] and library_worlds(tmp_path / "shot.mwb") == [0, 1, 2]
    assert [bpy.path.basename(item.path) for item in settings.libraries] == ["shot.mwb", "shot-2.mwb"]
    # Each library keeps the scene of its own run beside it.
    def box0_range(name):
        scene = json.loads((tmp_path / name).read_text())
        return next(b for b in scene["bodies"] if b["name"] == "Box0")["variation"]["location_max_m"]
    assert box0_range("shot.scene.json") == pytest.approx(old_max)
    assert box0_range("shot-2.scene.json") == pytest.approx((0.3, 0.3, 0.3))
    # Back to the first library: it opens, and its worlds are listed.
    settings.library_index = 0
    assert SESSION.view.path == str(tmp_path / "shot.mwb") and len(settings.worlds) == 3
    # The range as it was: Sample adds to the first library again, not to a third one.
    boxes[0].mwb_variation.location_max = old_max
    sample_and_wait(2)
    assert library_worlds(tmp_path / "shot.mwb") == [0, 1, 2, 3, 4] and not (tmp_path / "shot-3.mwb").exists()


def test_sample_after_cancel_finishes_the_interrupted_run(tmp_path):
    mwb = sample_then_cancel(tmp_path, 12)
    kept = len(SESSION.view.world_indices)
    assert kept < 12
    from many_worlds.operators import sampling
    assert sampling.interrupted_run(bpy.context.scene) == (0, 12)
    # Sample again (from a script: finish the interrupted run) fills the range, nothing beyond it.
    mwb.world_count = 3
    sample_and_wait(3)
    assert library_worlds(tmp_path / "shot.mwb") == list(range(12))
    assert sampling.interrupted_run(bpy.context.scene) is None
    sample_and_wait(3)
    assert library_worlds(tmp_path / "shot.mwb") == list(range(15))


def test_after_bake_sample_adds_to_the_same_library_and_the_ranges_stay(tmp_path):
    _, boxes = drop_scene(bodies=2)
    save_blend(tmp_path)
    sample_and_wait(2)
    bpy.ops.mwb.select_world(world=1)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    assert all(box.rigid_body is not None for box in boxes), "the variation panel needs the rigid body"
    sample_and_wait(2)
    assert SESSION.last_error == "", SESSION.last_error
    assert library_worlds(tmp_path / "shot.mwb") == [0, 1, 2, 3] and not (tmp_path / "shot-2.mwb").exists()


def test_an_unsampleable_scene_is_refused_before_the_engine_starts(tmp_path):
    drop_scene(bodies=1)
    save_blend(tmp_path)
    bpy.data.objects["Box0"].rigid_body.mass = 0.0
    bpy.data.objects["Box0"].rigid_body.collision_shape = "MESH"
    with pytest.raises(RuntimeError, match="mass_kg must be > 0"):
        bpy.ops.mwb.sample()
    assert SESSION.run is None
    assert not os.path.exists(str(tmp_path / "shot.mwb"))


def run_cli(blend, *args):
    """The add-on's command line in another Blender, as a farm task runs it."""
    cli = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(many_worlds.__file__))), "many_worlds", "cli.py")
    result = subprocess.run(["blender", "-b", blend, "--python-exit-code", "1", "--python", cli, "--", *args],
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-1500:] + result.stderr[-1500:]
    return result.stdout


def json_output(text):
    """The JSON document a command printed after Blender's own banner and log lines."""
    start = re.search(r"^\{", text, re.M)
    assert start is not None, text[-1500:]
    return json.loads(text[start.start():])


# One thread: worlds are stored in the order they finish, so only then is the file order fixed too.
NON_DEFAULT_SETTINGS = dict(seed=7, alpha=0.3, stop_at_rest=False, duration_s=1.25, position_error_mm=2.0,
                            rotation_error_deg=1.5, threads=1)


def test_sample_button_command_line_and_farm_shards_make_one_library(tmp_path):
    """The same .blend and world range give byte-identical libraries from the Sample button and
    from the command line, with the scene's non-default run settings; a farm task's shard of the
    next worlds merges into the library the button started."""
    drop_scene(bodies=2)
    for key, value in NON_DEFAULT_SETTINGS.items():
        setattr(bpy.context.scene.mwb, key, value)
    blend = save_blend(tmp_path)
    sample_and_wait(4)
    button = str(tmp_path / "shot.mwb")
    assert SESSION.view.path == button and len(SESSION.view.world_indices) == 4
    from_cli = str(tmp_path / "cli.mwb")
    run_cli(blend, "sample", "--worlds", "0:4", "--out", from_cli)
    with open(button, "rb") as a, open(from_cli, "rb") as b:
        assert a.read() == b.read(), "the command line must sample exactly what the Sample button does"

    info = json_output(run_cli(blend, "info", button, "--json"))
    run = info["run"]
    assert run["base_seed"] == 7 and run["alpha_linear"] == pytest.approx(0.3) and run["stop_at_rest"] is False
    assert run["duration_s"] == pytest.approx(1.25) and run["position_error_max_m"] == pytest.approx(0.002)
    assert run["rotation_error_max_deg"] == pytest.approx(1.5)
    defaults = str(tmp_path / "defaults.mwb")
    engine = os.path.join(os.path.dirname(many_worlds.__file__), "bin", "mwb-engine")
    subprocess.run([engine, "sample", "--scene", str(tmp_path / "shot.scene.json"), "--out", defaults,
                    "--worlds", "0:1"], check=True, capture_output=True)
    assert json.loads(subprocess.run([engine, "info", defaults, "--json"], capture_output=True,
                                     text=True).stdout)["run_hash"] != info["run_hash"]

    from many_worlds.farm import plan
    task = plan.sample_command(blend, 4, 6, str(tmp_path / "farm"))
    subprocess.run(task, check=True, capture_output=True)
    merged = str(tmp_path / "merged.mwb")
    run_cli(blend, "merge", merged, button, str(tmp_path / "farm" / plan.shard_name(4, 6)))
    assert sorted(_native.Library(merged).world_indices) == list(range(6))


def test_settings_the_engine_does_not_reproduce_are_listed_by_object_and_setting(tmp_path):
    _, boxes = drop_scene(bodies=1)
    boxes[0].scale = (-1, 1, 1)
    save_blend(tmp_path)
    assert bpy.ops.mwb.check_scene() == {"FINISHED"}
    assert any(line.startswith("Box0: scale:") for line in SESSION.export_warnings), SESSION.export_warnings
    sample_and_wait(1)
    assert any(line.startswith("Box0: scale:") for line in SESSION.export_warnings)
