"""Library.polylines: the chosen bodies' paths of many worlds in one array, equal to what
Library.polyline gives world by world."""
import json
import os

import numpy as np
import pytest

from conftest import SCENES, run_engine

QUICKSTART = os.path.join(SCENES, "quickstart.json")


def thinned(points, stride):
    """Point indices kept at `stride`: 0, stride, 2 stride, ... and the last."""
    kept = list(range(0, points, stride))
    return kept if kept[-1] == points - 1 else kept + [points - 1]


@pytest.fixture(scope="module")
def library(native, engine, tmp_path_factory):
    """Quick-start worlds 0..2, world 3 refined from 0 with a pebble added (absent from 0..2) and
    world 4 refined from 1 without the chute; worlds end at rest at different frames."""
    tmp = tmp_path_factory.mktemp("polylines")
    out = tmp / "lib.mwb"
    result = run_engine(engine, "sample", "--scene", QUICKSTART, "--out", str(out), "--seed", "4",
                        "--worlds", "0:3", "--threads", "2")
    assert result.returncode == 0, result.stderr
    with open(QUICKSTART) as f:
        scene = json.load(f)
    scene["bodies"].append({"name": "Pebble", "type": "ACTIVE", "shape": {"type": "SPHERE", "radius_m": 0.1},
                            "initial": {"location": [4.0, 4.0, 1.0]}})
    (tmp / "pebble.json").write_text(json.dumps(scene))
    for args in (["--world", "0", "--add", "Pebble", "--scene", str(tmp / "pebble.json")],
                 ["--world", "1", "--remove", "Chute"]):
        result = run_engine(engine, "refine", "--library", str(out), *args, "--count", "1")
        assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    assert sorted(lib.world_indices) == [0, 1, 2, 3, 4]  # file order: as the threads finished
    return lib


@pytest.mark.parametrize("stride", [1, 2, 7, 1000])
def test_polylines_equal_polyline_world_by_world(library, stride):
    worlds = [4, 0, 3, 2, 1]
    bodies = list(range(library.body_count))[::-1]
    gathered = library.polylines(worlds, bodies, stride)
    assert gathered.dtype == np.float32 and gathered.shape[:2] == (len(worlds), len(bodies))
    for i, world in enumerate(worlds):
        whole = library.polyline(world)
        kept = thinned(whole.shape[1], stride)
        expected = whole[bodies][:, kept]
        np.testing.assert_array_equal(gathered[i, :, :len(kept)], expected)
        # Shorter paths are padded with NaN up to the longest.
        assert np.isnan(gathered[i, :, len(kept):]).all()
    assert gathered.shape[2] == max(len(thinned(library.polyline(w).shape[1], stride)) for w in worlds)


def test_absent_bodies_are_nan(library):
    names = [b["name"] for b in json.loads(library.scene_json)["bodies"]]
    pebble, chute = names.index("Pebble"), names.index("Chute")
    gathered = library.polylines([0, 3, 4], [pebble, chute], 3)
    assert np.isnan(gathered[0, 0]).all(), "world 0 was sampled before the pebble"
    assert np.isfinite(gathered[1, 0, 0]).all() and np.isfinite(gathered[1, 1, 0]).all()
    assert np.isnan(gathered[2, 1]).all(), "world 4 has no chute"


def test_empty_requests_give_empty_arrays(library):
    assert library.polylines([], [0, 1], 2).shape == (0, 2, 0, 3)
    assert library.polylines([0, 1], [], 2).shape[:2] == (2, 0)


def test_mistakes_are_clear_errors(library):
    with pytest.raises(KeyError, match="no world 99"):
        library.polylines([0, 99], [0], 1)
    with pytest.raises(IndexError, match=f"body {library.body_count} out of range"):
        library.polylines([0], [0, library.body_count], 1)
    with pytest.raises(IndexError, match="body -1 out of range"):
        library.polylines([0], [-1], 1)
    with pytest.raises(ValueError, match="stride must be at least 1, got 0"):
        library.polylines([0], [0], 0)
