"""World points to pixels (many_worlds.core.screen_pixels), thinning paths in screen space
(many_worlds.core.screen_thinning) and the drawing budget with it."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "shared"))

from camera_math import look_at, perspective  # noqa: E402
from many_worlds.core import path_budget, screen_thinning  # noqa: E402
from many_worlds.core.screen_pixels import world_to_pixels  # noqa: E402

VIEW = screen_thinning.ScreenView(tuple(map(tuple, perspective(0.8, 1.6, 0.1, 100) @ look_at([6, -6, 4], [0, 0, 1]))),
                                  1600, 1000)


def test_pixels_count_rows_up_from_the_bottom_or_down_from_the_top():
    # Looking along +y from the origin: the target at the centre, a point above it in the upper
    # half, one to its right in the right half, one behind the eye not in front.
    eye = perspective(0.8, 1.6, 0.1, 100) @ look_at([0, 0, 0], [0, 5, 0])
    points = np.array([[0, 5, 0], [0, 5, 1], [1, 5, 0], [0, -5, 0]], np.float64)
    x, up, in_front = world_to_pixels(points, eye, (1600, 1000))
    _, down, _ = world_to_pixels(points, eye, (1600, 1000), y_down=True)
    assert np.allclose([x[0], up[0], down[0]], [800, 500, 500])
    assert up[1] > 500 > down[1] and np.isclose(up[1] + down[1], 1000)
    assert x[2] > 800 and list(in_front) == [True, True, True, False]
    # The viewport's thinning sees the same pixels, in float32.
    view = screen_thinning.ScreenView(tuple(map(tuple, eye)), 1600, 1000)
    thin_x, thin_y, _ = screen_thinning.pixels(points.astype(np.float32), view)
    assert thin_x.dtype == np.float32 and np.allclose(thin_x, x) and np.allclose(thin_y, up)


def paths(count=50, points=301, seed=1):
    """float32 (count, points, 3): falling random walks that come to rest a third of the way in,
    one shorter (NaN after its end) and one absent (all NaN)."""
    rng = np.random.default_rng(seed)
    steps = rng.normal(scale=0.004, size=(count, points, 3)) - [0, 0, 0.01]
    out = rng.uniform(-1, 1, size=(count, 1, 3)) + [0, 0, 2] + np.cumsum(steps, axis=1)
    out[..., 2] = np.maximum(out[..., 2], 0)
    out[:, points // 3:] = out[:, points // 3 - 1:points // 3]
    out[3, points * 2 // 3:] = np.nan
    out[4] = np.nan
    return out.astype(np.float32)


def test_thinning_keeps_ends_and_every_vertex_a_pixel_from_the_last_kept():
    lines = paths()
    keep = screen_thinning.kept_on_screen(lines, VIEW)
    x, y, _ = screen_thinning.pixels(np.nan_to_num(lines), VIEW)
    xy = np.stack([x, y], axis=-1)
    finite = np.isfinite(lines[..., 0])
    assert not keep[~finite].any(), "NaN points are never kept"
    assert keep.sum() < 0.5 * finite.sum(), "paths at rest thin to a few points"
    for p in range(len(lines)):
        indices = np.flatnonzero(finite[p])
        if len(indices) == 0:
            continue
        assert keep[p, indices[0]] and keep[p, indices[-1]], "each path keeps its first and last point"
        last = indices[0]
        for j in indices[1:]:
            if np.linalg.norm(xy[p, j] - xy[p, last]) > VIEW.tolerance_px:
                assert keep[p, j], f"path {p} point {j} is more than a pixel from the last kept one"
            if keep[p, j]:
                last = j


def test_thinned_segments_join_the_kept_points_unmoved():
    lines = paths()
    keep = screen_thinning.kept_on_screen(lines, VIEW)
    vertices, path_of = path_budget.joined_segments(lines, keep)
    expected = []
    for p in range(len(lines)):
        kept = lines[p, keep[p]]
        for a, b in zip(kept[:-1], kept[1:]):
            expected += [a, b]
    assert np.array_equal(vertices, np.array(expected, np.float32).reshape(-1, 3))
    assert list(path_of) == [p for p in range(len(lines)) for _ in range(max(0, keep[p].sum() - 1))]


def test_a_sharp_turn_within_a_pixel_of_the_last_kept_point_is_kept():
    # Out along x and straight back, steps of about a pixel (drawn at the origin, about 2 m from the
    # eye): the turning point stays.
    eye_view = screen_thinning.ScreenView(
        tuple(map(tuple, perspective(0.8, 1.6, 0.1, 100) @ look_at([0, -2, 0], [0, 0, 0]))), 1600, 1000)
    xs = np.r_[np.arange(10), np.arange(8, -1, -1)] * 0.0016
    line = np.stack([xs, np.zeros_like(xs), np.zeros_like(xs)], axis=-1).astype(np.float32)[None]
    keep = screen_thinning.kept_on_screen(line, eye_view)
    assert keep[0, 9], "the turning point is kept"


def test_more_worlds_fit_the_budget_when_thinned_on_screen():
    pool = paths(count=8, points=101)
    pool = np.stack([pool[:4], pool[4:]])   # 2 kinds of worlds x 4 bodies

    def polylines_of(worlds, bodies, stride):
        kept = path_budget.thinned_indices(pool.shape[2], stride)
        return pool[np.asarray(worlds)[:, None, None] % 2, np.asarray(bodies, np.intp)[None, :, None], kept]

    choice = path_budget.PathChoice(list(range(400)), np.ones(400, bool), -1, (0, 1, 2, 3), (),
                                    [(1, 0, 0)] * 4)
    budget = 100 * 3 * 2 * path_budget.MIN_SEGMENTS
    plain = path_budget.build_path_arrays(choice, polylines_of, budget)
    thinned = path_budget.build_path_arrays(choice, polylines_of, budget, VIEW)
    assert plain.vertex_count <= budget and thinned.vertex_count <= budget
    assert thinned.worlds_drawn > plain.worlds_drawn
    assert thinned.budget_text() == f"Showing {thinned.worlds_drawn} of 400 worlds' paths (drawing budget)"
    assert len(thinned.other_colours) == len(thinned.others)
