"""The drawing budget's choices (many_worlds.core.path_budget), in plain Python on synthetic paths."""
import numpy as np

from many_worlds.core import path_budget

BODIES, POINTS = 4, 101
COLOURS = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0, 0.0)]


def polyline_of(world):
    t = np.linspace(0, 1, POINTS, dtype=np.float32)
    return np.stack([np.stack([t * (b + 1), t * world, t], axis=-1) for b in range(BODIES)])


def polylines_of(absent=None):
    """Library.polylines over polyline_of's worlds; `absent`: a (world, body) the world lacks."""
    def read(worlds, bodies, stride):
        points = len(path_budget.thinned_indices(POINTS, stride))
        out = np.full((len(worlds), len(bodies), points, 3), np.nan, np.float32)
        for i, world in enumerate(worlds):
            for j, body in enumerate(bodies):
                if (world, body) != absent:
                    out[i, j] = polyline_of(world)[body, path_budget.thinned_indices(POINTS, stride)]
        return out
    return read


def build(matching, selected=-1, preferred=(), budget=path_budget.VERTEX_BUDGET, absent=None, screen=None):
    worlds = list(range(len(matching)))
    choice = path_budget.PathChoice(worlds, np.asarray(matching, bool), selected, tuple(range(BODIES)),
                                    preferred, COLOURS)
    return path_budget.build_path_arrays(choice, polylines_of(absent), budget, screen)


def test_thinning_keeps_the_first_every_stride_th_and_the_last_point():
    assert list(path_budget.thinned_indices(10, 4)) == [0, 4, 8, 9]
    assert list(path_budget.thinned_indices(9, 4)) == [0, 4, 8]
    assert path_budget.path_vertices(101, 1) == 200 and path_budget.path_vertices(1, 1) == 0
    assert path_budget.stride_to_fit(101, 10, 2000) == 1
    assert path_budget.stride_to_fit(101, 10, 1000) == 2
    # Never coarser than MIN_SEGMENTS segments a path, however small the budget.
    assert path_budget.stride_to_fit(101, 10, 1) == 100 // path_budget.MIN_SEGMENTS


def test_every_beginning_of_the_spread_order_covers_the_range():
    order = path_budget.spread_order(1000)
    assert sorted(order) == list(range(1000))
    first = np.sort(order[:10])
    assert first[0] == 0 and np.all(np.diff(first) >= 64)


def test_within_the_budget_everything_is_drawn_in_full():
    arrays = build([True, False, True], selected=1)
    assert arrays.complete and arrays.worlds_drawn == 3 and arrays.budget_text() == ""
    assert len(arrays.selected) == BODIES * 200 and len(arrays.others) == 2 * BODIES * 200
    assert arrays.other_colours.shape == (len(arrays.others), 4)
    expected = path_budget.line_segments(polyline_of(1), tuple(range(BODIES)), 1)
    assert np.array_equal(arrays.selected, expected)


def test_over_budget_the_selected_world_and_matched_preferred_paths_come_first():
    matching = [k % 4 == 0 for k in range(40)]
    budget = BODIES * 200 + 10 * 2 * path_budget.MIN_SEGMENTS * 2 + 50
    arrays = build(matching, selected=5, preferred=(2,), budget=budget)
    assert arrays.vertex_count <= budget and not arrays.complete
    drawn = {(w, bodies) for w, bodies, _ in arrays.drawn}
    assert (5, tuple(range(BODIES))) in drawn
    for world in range(0, 40, 4):
        assert (world, (2,)) in drawn
    assert arrays.budget_text() == f"Showing {arrays.worlds_drawn} of 40 worlds' paths (drawing budget)"


def test_absent_bodies_are_not_drawn():
    arrays = build([True, True], absent=(1, 3))
    assert (1, (0, 1, 2), 1) in arrays.drawn and arrays.paths_drawn == 2 * BODIES - 1
