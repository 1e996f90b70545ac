"""Which paths the viewport draws within its vertex budget, and their vertex and colour arrays
(bpy-free: draw.paths turns the arrays into GPU batches).

Paths are drawn as line lists (two vertices per segment). The selected world's paths are always
drawn in full. The other paths are taken tier by tier: matched worlds' preferred bodies (the
selected objects'), matched worlds' other bodies, then the same for rejected worlds. A tier is
thinned by a stride (every stride-th recorded point, and the last) just enough to fit what is left
of the budget, down to MIN_SEGMENTS segments a path; when even that does not fit, the tier draws
the worlds that fit, taken in an order whose every beginning is spread evenly over the library
(bit-reversed positions), and later tiers draw nothing.
"""
import functools
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

from . import palette

# Vertices the viewport draws at most (line-list vertices: two per segment).
VERTEX_BUDGET = 2_000_000
# A thinned path keeps at least this many segments (or all it has).
MIN_SEGMENTS = 16
# While a world is selected, the other paths' alpha is scaled by this, so the selected one stands out.
DIMMED_ALPHA = 0.35
SELECTED_COLOR = (0.1, 0.85, 1.0, 1.0)


@functools.lru_cache(maxsize=64)
def thinned_indices(points, stride):
    """Indices of the points a path of `points` keeps at `stride`: 0, stride, 2 stride, ... and the
    last (shared between calls: not to be written to)."""
    if points < 2:
        return np.zeros(0, np.intp)
    kept = np.arange(0, points, max(1, stride), dtype=np.intp)
    kept = kept if kept[-1] == points - 1 else np.append(kept, points - 1)
    kept.flags.writeable = False
    return kept


def path_vertices(points, stride):
    """Line-list vertices of one path of `points` points thinned at `stride`."""
    return 2 * max(0, len(thinned_indices(points, stride)) - 1)


def stride_to_fit(points, paths, budget):
    """The smallest stride at which `paths` paths of `points` points fit `budget` vertices, but
    none coarser than keeping MIN_SEGMENTS segments a path."""
    coarsest = max(1, (points - 1) // MIN_SEGMENTS)
    stride = 1
    while stride < coarsest and paths * path_vertices(points, stride) > budget:
        # Vertices fall about as 1/stride: jump close to the answer, then step.
        stride = max(stride + 1, min(coarsest, int(stride * paths * path_vertices(points, stride) / max(budget, 1))))
    while stride > 1 and paths * path_vertices(points, stride - 1) <= budget:
        stride -= 1
    return stride


def spread_order(count):
    """A permutation of range(count) whose every beginning is spread evenly over the range:
    positions sorted by their bit-reversed value."""
    if count <= 1:
        return np.arange(count, dtype=np.intp)
    bits = int(count - 1).bit_length()
    positions = np.arange(count, dtype=np.uint64)
    reversed_bits = np.zeros(count, dtype=np.uint64)
    for b in range(bits):
        reversed_bits |= ((positions >> np.uint64(b)) & np.uint64(1)) << np.uint64(bits - 1 - b)
    return np.argsort(reversed_bits, kind="stable").astype(np.intp)


def line_segments(polyline, bodies, stride):
    """Line-list vertices float32 (len(bodies) * path_vertices, 3) of the given bodies' paths of
    `polyline` (float32 (bodies, points, 3)) thinned at `stride`, body after body."""
    kept = thinned_indices(polyline.shape[1], stride)
    if len(bodies) == 0 or len(kept) < 2:
        return np.zeros((0, 3), np.float32)
    paths = polyline[np.asarray(bodies, dtype=np.intp)[:, None], kept[None, :]]
    out = np.empty((len(bodies), len(kept) - 1, 2, 3), np.float32)
    out[:, :, 0] = paths[:, :-1]
    out[:, :, 1] = paths[:, 1:]
    return out.reshape(-1, 3)


@dataclass(frozen=True)
class PathChoice:
    """What to draw, as the add-on's state says it.

    worlds: world indices in file order; matching: bool per world (already False for worlds outside
    the selected world's family when only the family is shown); selected: the selected world or -1;
    bodies: body indices whose paths are drawn; preferred: those of them kept first (the selected
    objects'); body_colours: (r, g, b) per body index.
    """
    worlds: Sequence[int]
    matching: np.ndarray
    selected: int
    bodies: tuple
    preferred: tuple
    body_colours: Sequence[tuple]


@dataclass
class PathArrays:
    """Line-list vertices and their colours, ready for GPU batches.

    others, other_colours: float32 (n, 3) and (n, 4), every world but the selected one, rejected
    before matched (so matched ones draw over them); selected, selected_colours: the selected
    world's paths (drawn on top). Counts say how much of the library is drawn.
    """
    others: np.ndarray
    other_colours: np.ndarray
    selected: np.ndarray
    selected_colours: np.ndarray
    worlds_total: int = 0
    worlds_drawn: int = 0
    paths_drawn: int = 0
    complete: bool = True       # no path was left out (some may be thinned)
    coarsest_stride: int = 1
    worlds: set = field(default_factory=set)            # the worlds drawn
    drawn: list = field(default_factory=list)           # (world, bodies, stride) of each part drawn
    segments: dict = field(default_factory=dict)        # (world, bodies, stride) -> line-list vertices

    @property
    def vertex_count(self):
        return len(self.others) + len(self.selected)

    def budget_text(self):
        """The panel's line when the budget leaves paths out ("" when everything is drawn)."""
        if self.complete:
            return ""
        if self.worlds_drawn < self.worlds_total:
            return f"Showing {self.worlds_drawn:,} of {self.worlds_total:,} worlds' paths (drawing budget)"
        return f"Showing some paths of all {self.worlds_total:,} worlds (drawing budget)"


def _tiers(choice):
    """[(world positions in the order they are taken, bodies, matched)] of the non-selected worlds."""
    positions = np.array([k for k, w in enumerate(choice.worlds) if w != choice.selected], dtype=np.intp)
    matching = np.asarray(choice.matching, dtype=bool)[positions] if len(positions) else np.zeros(0, bool)
    preferred = tuple(b for b in choice.bodies if b in set(choice.preferred))
    rest = tuple(b for b in choice.bodies if b not in set(preferred))
    tiers = []
    for matched in (True, False):
        subset = positions[matching == matched]
        subset = subset[spread_order(len(subset))]
        for bodies in (preferred, rest):
            if len(subset) and bodies:
                tiers.append((subset, bodies, matched))
    return tiers


def build_path_arrays(choice: PathChoice, polyline_of: Callable, present_of: Callable,
                      budget: int = VERTEX_BUDGET, cache: Optional[dict] = None):
    """The arrays of the paths `choice` draws within `budget` vertices.

    polyline_of(world) -> float32 (bodies, points, 3); present_of(world, bodies) -> the bodies of
    `bodies` the world has. cache: the `segments` of the previous PathArrays, whose thinned
    segments are reused. Each world's polyline is read at most once.
    """
    worlds = list(choice.worlds)
    cache = cache or {}
    segments, read = {}, {}

    def read_once(world):
        if world not in read:
            read[world] = polyline_of(world)
        return read[world]

    plan, tiers_left_out = _plan(choice, worlds, budget - _selected_size(choice, worlds, present_of, read_once),
                                 read_once)
    needs = {}   # world -> [(bodies, stride)] of every tier expected to draw it
    for positions, bodies, _, stride, fit in plan:
        for k in positions[:fit]:
            needs.setdefault(worlds[k], []).append((bodies, stride))

    def part(world, bodies, stride):
        key = (world, bodies, stride)
        if key not in cache:
            # Thin everything this build may take of the world from one read of its polyline.
            lines = read.pop(world, None)
            lines = polyline_of(world) if lines is None else lines
            for tier_bodies, tier_stride in needs.get(world, []) + [(bodies, stride)]:
                present = present_of(world, tier_bodies)
                if (world, present, tier_stride) not in cache:
                    cache[(world, present, tier_stride)] = line_segments(lines, present, tier_stride)
        segments[key] = cache[key]
        return cache[key]

    arrays = PathArrays(*[np.zeros((0, n), np.float32) for n in (3, 4, 3, 4)], worlds_total=len(worlds),
                        segments=segments)
    if choice.selected in worlds:
        bodies = present_of(choice.selected, choice.bodies)
        arrays.selected = part(choice.selected, bodies, 1)
        arrays.selected_colours = _colours(bodies, len(arrays.selected), _rgba(choice))
        budget -= len(arrays.selected)
        arrays.paths_drawn += len(bodies)
        arrays.worlds.update([choice.selected] if bodies else [])
        arrays.drawn.append((choice.selected, bodies, 1))
    shades = {True: np.array([palette.matching(c) for c in choice.body_colours], np.float32).reshape(-1, 4),
              False: np.array([palette.rejected(c) for c in choice.body_colours], np.float32).reshape(-1, 4)}
    if choice.selected in worlds:
        for table in shades.values():
            table[:, 3] *= DIMMED_ALPHA
    taken = {True: ([], []), False: ([], [])}
    colours = {}   # (bodies, vertices, matched) -> their colours: worlds share them
    full = False   # a world did not fit: what is not taken yet is left out
    for positions, bodies, matched, stride, _ in plan:
        arrays.coarsest_stride = max(arrays.coarsest_stride, stride)
        for k in positions:
            present = present_of(worlds[k], bodies)
            lines = part(worlds[k], present, stride)
            if len(lines) > budget:
                full = True
                break
            budget -= len(lines)
            if len(lines):
                taken[matched][0].append(lines)
                key = (present, len(lines), matched)
                if key not in colours:
                    colours[key] = _colours(present, len(lines), shades[matched])
                taken[matched][1].append(colours[key])
                arrays.worlds.add(worlds[k])
                arrays.drawn.append((worlds[k], present, stride))
                arrays.paths_drawn += len(present)
        if full:
            break
    arrays.complete = not (full or tiers_left_out)
    arrays.others = _concatenate(taken[False][0] + taken[True][0], 3)
    arrays.other_colours = _concatenate(taken[False][1] + taken[True][1], 4)
    arrays.worlds_drawn = len(arrays.worlds)
    return arrays


def _selected_size(choice, worlds, present_of, polyline):
    """Vertices of the selected world's full paths (0 without one)."""
    if choice.selected not in worlds:
        return 0
    return len(present_of(choice.selected, choice.bodies)) * path_vertices(polyline(choice.selected).shape[1], 1)


def _plan(choice, worlds, budget, polyline):
    """([(world positions, bodies, matched, stride, worlds expected to fit)], whether tiers are left
    out) in the order tiers are taken: each thinned to fit what the tiers before it leave (a path's
    points estimated from the tier's first world); the first tier that does not fit in full is the
    last. The caller takes worlds while their real size fits."""
    plan = []
    tiers = _tiers(choice)
    for t, (positions, bodies, matched) in enumerate(tiers):
        points = polyline(worlds[positions[0]]).shape[1]
        stride = stride_to_fit(points, len(positions) * len(bodies), budget)
        per_world = len(bodies) * path_vertices(points, stride)
        fit = len(positions) if per_world == 0 else min(len(positions), budget // per_world)
        plan.append((positions, bodies, matched, stride, fit))
        budget -= fit * per_world
        if fit < len(positions):
            return plan, t + 1 < len(tiers)
    return plan, False


def selected_band_colours(count):
    """float32 (count, 4): the selected world's band, under its paths' own colours."""
    return np.broadcast_to(np.asarray(SELECTED_COLOR, np.float32), (count, 4))


def _rgba(choice):
    return np.array([tuple(c[:3]) + (1.0,) for c in choice.body_colours], np.float32).reshape(-1, 4)


def _colours(bodies, vertex_count, table):
    """float32 (vertex_count, 4): each body's row of `table` over its equal share of the vertices."""
    if not bodies:
        return np.zeros((0, 4), np.float32)
    return np.repeat(table[np.asarray(bodies, dtype=np.intp)], vertex_count // len(bodies), axis=0)


def _concatenate(parts, width):
    return np.concatenate(parts) if parts else np.zeros((0, width), np.float32)
