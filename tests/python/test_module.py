"""The native module through its Python API: scenes, sampling, recorded arrays, errors."""
import json
import os
import threading

import numpy as np
import pytest


def test_scene_round_trips_through_json(native, scene_text):
    scene = native.Scene.from_json(scene_text("all_shapes_and_joints.json"))
    again = native.Scene.from_json(scene.to_json())
    assert again.to_json() == scene.to_json()
    assert "Door" in scene.body_names and "DoorHinge" in scene.constraint_names


def test_invalid_scene_raises_with_every_problem_named(native, scene_text):
    data = json.loads(scene_text("quickstart.json"))
    data["bodies"][2]["mass_kg"] = -1
    data["bodies"][3]["shape"]["type"] = "TEAPOT"
    with pytest.raises(native.SceneError) as error:
        native.Scene.from_json(json.dumps(data))
    message = str(error.value)
    assert "Marble" in message and "mass_kg" in message
    assert "Die" in message and "TEAPOT" in message
    problems = native.validate_scene_json(json.dumps(data))
    assert len(problems) >= 2


@pytest.mark.parametrize("text", ["", "{", "[]", '{"format": "mwb-scene"}', "null", '{"format": "other", "version": 1}'])
def test_malformed_scene_text_is_a_scene_error(native, text):
    with pytest.raises(native.SceneError):
        native.Scene.from_json(text)


def test_world_arrays_have_documented_shapes_and_units(native, scene_text):
    scene = native.Scene.from_json(scene_text("quickstart.json"))
    worlds = native.sample(scene, native.SimulationParameters(), base_seed=3, first_world=0, world_count=2, threads=1)
    assert [w.world_index for w in worlds] == [0, 1]
    w = worlds[0]
    assert w.status == "ok"
    bodies = len(scene.body_names)
    assert w.positions.shape == (bodies, w.frame_count, 3) and w.positions.dtype == np.float64
    assert w.orientations.shape == (bodies, w.frame_count, 4)
    np.testing.assert_allclose(np.linalg.norm(w.orientations, axis=2), 1.0, atol=1e-9)
    assert w.frame_count == round(w.simulated_time_s * w.record_hz) + 1
    # The marble starts where the scene put it (within its variation) and ends lower.
    marble = scene.body_names.index("Marble")
    assert abs(w.positions[marble, 0, 2] - 1.5) <= 0.05 + 1e-9
    assert w.positions[marble, -1, 2] < 1.0
    contacts = w.contacts
    assert set(contacts) == {"time_s", "body", "other", "impulse_ns"}
    assert len(contacts["time_s"]) == len(contacts["body"]) > 0
    assert np.all(np.diff(contacts["time_s"]) >= 0)
    first = w.checkpoints[0]
    assert first["time_s"] == 0.0 and first["com_position_m"].shape == (bodies, 3)


def test_same_worlds_from_one_or_two_threads(native, scene_text):
    scene = native.Scene.from_json(scene_text("all_shapes_and_joints.json"))
    params = native.SimulationParameters()
    one = {w.world_index: w.hash for w in native.sample(scene, params, 11, 0, 6, threads=1)}
    two = {w.world_index: w.hash for w in native.sample(scene, params, 11, 0, 6, threads=2)}
    shard = {w.world_index: w.hash for w in native.sample(scene, params, 11, 3, 3, threads=2)}
    assert one == two
    assert all(one[k] == shard[k] for k in shard)
    assert len(set(one.values())) == 6


def test_quickstep_uses_the_engines_generator_inside_this_process(native, scene_text):
    # The override of ODE's dRandInt must win inside a dlopen'ed extension too.
    scene = native.Scene.from_json(scene_text("quickstart.json"))
    before = native.ode_random_calls_on_this_thread()
    native.sample(scene, native.SimulationParameters(), 1, 0, 1, threads=1)
    # OpenMP with one thread runs the loop on the calling thread.
    assert native.ode_random_calls_on_this_thread() - before > 1000


def test_worlds_stream_to_the_callback_as_they_finish(native, scene_text):
    scene = native.Scene.from_json(scene_text("quickstart.json"))
    seen = []
    worlds = native.sample(scene, native.SimulationParameters(), 5, 10, 4, threads=2,
                           on_world=lambda w: seen.append(w.world_index))
    assert sorted(seen) == [10, 11, 12, 13]
    assert [w.world_index for w in worlds] == [10, 11, 12, 13]


def test_sampling_releases_the_gil(native, scene_text):
    scene = native.Scene.from_json(scene_text("all_shapes_and_joints.json"))
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.005)

    thread = threading.Thread(target=ticker)
    thread.start()
    native.sample(scene, native.SimulationParameters(), 1, 0, 8, threads=1)
    stop.set()
    thread.join()
    assert len(ticks) > 5, "a Python thread kept running while worlds were simulated"


def test_callback_exception_propagates_and_stops_the_run(native, scene_text):
    scene = native.Scene.from_json(scene_text("quickstart.json"))

    def fail(world):
        raise RuntimeError("sink broke")

    with pytest.raises(RuntimeError, match="sink broke"):
        native.sample(scene, native.SimulationParameters(), 1, 0, 4, threads=2, on_world=fail)


def test_bad_parameters_are_errors_not_crashes(native, scene_text):
    scene = native.Scene.from_json(scene_text("quickstart.json"))
    params = native.SimulationParameters()
    params.alpha_linear = 3.0
    with pytest.raises(native.SceneError, match="alpha_linear"):
        native.sample(scene, params, 1, 0, 1)
    with pytest.raises(TypeError):
        native.sample(scene, "not parameters", 1, 0, 1)
    with pytest.raises(TypeError):
        native.sample(scene, native.SimulationParameters(), -1, 0, 1)


def test_the_type_stubs_declare_every_public_name_of_the_module(native):
    """addon/many_worlds/_native.pyi is what editors and readers see: it must not fall behind."""
    import ast
    stub_path = os.path.join(os.path.dirname(native.__file__), "_native.pyi")
    tree = ast.parse(open(stub_path).read())
    declared = {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            declared[node.name] = {n.target.id if isinstance(n, ast.AnnAssign) else n.name
                                   for n in node.body if isinstance(n, (ast.AnnAssign, ast.FunctionDef))}
        elif isinstance(node, ast.FunctionDef):
            declared[node.name] = set()
    for name in (n for n in dir(native) if not n.startswith("_")):
        assert name in declared, f"_native.{name} is missing from _native.pyi"
        value = getattr(native, name)
        if isinstance(value, type) and not issubclass(value, Exception):
            members = {m for m in dir(value) if not m.startswith("_")}
            assert members <= declared[name], f"_native.{name}: {sorted(members - declared[name])} missing from the stub"
