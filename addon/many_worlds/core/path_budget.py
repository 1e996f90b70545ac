"""Which paths the viewport draws within its vertex budget, and their vertex and colour arrays
(bpy-free: draw.paths turns the arrays into GPU batches).

Paths are drawn as line lists (two vertices per segment). The selected world's paths are always
drawn in full. The other paths are taken tier by tier: matched worlds' preferred bodies (the
selected objects'), matched worlds' other bodies, then the same for rejected worlds. A tier is
thinned by a stride (every stride-th recorded point, and the last) just enough to fit what is left
of the budget, down to MIN_SEGMENTS segments a path; when even that does not fit, the tier draws
the worlds that fit, taken in an order whose every beginning is spread evenly over the library
(bit-reversed positions), and later tiers draw nothing. Given the view, a tier's paths are also
thinned in screen space (core.screen_thinning) before worlds are counted against the budget.
Only the bodies a tier draws are read from the library, for many worlds at once.
"""
import functools
import itertools
from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

from .. import _native
from . import palette, screen_thinning

# Vertices the viewport draws at most (line-list vertices: two per segment).
VERTEX_BUDGET = 2_000_000
# A thinned path keeps at least this many segments (or all it has).
MIN_SEGMENTS = 16
# While a world is selected, the other paths' alpha is scaled by this, so the selected one stands out.
DIMMED_ALPHA = 0.35
SELECTED_COLOR = (0.1, 0.85, 1.0, 1.0)
# Thinned on screen, a tier's stride is chosen from about this many points of a sample of its
# worlds, expected to fill at most this share of the budget (the rest is spread differently).
SAMPLE_POINTS = 100_000
SAMPLE_MARGIN = 0.9


@functools.lru_cache(maxsize=64)
def thinned_indices(points, stride):
    """Indices of the points a path of `points` keeps at `stride`: 0, stride, 2 stride, ... and the
    last, by the module's rule, the one Library.polylines gathers by (shared between calls: not to
    be written to)."""
    kept = _native.thinned_indices(int(points), max(1, int(stride))).astype(np.intp, copy=False)
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
    return joined_segments(paths, np.ones(paths.shape[:2], bool))[0]


def joined_segments(paths, keep):
    """(line-list vertices float32 (2 segments, 3), the path index of each segment) joining each
    path's kept points in order; paths float32 (..., points, 3), keep bool (..., points). Paths are
    numbered in C order of the leading axes."""
    points = paths.shape[-2]
    paths, keep = paths.reshape(-1, points, 3), keep.reshape(-1, points)
    if points < 2:
        return np.zeros((0, 3), np.float32), np.zeros(0, np.intp)
    # Paths whose kept points are all their first ones (not thinned on screen) join neighbours:
    # strided copies, much faster than gathering kept points one by one.
    ends = keep[:, 1:]
    if not np.any(ends & ~keep[:, :-1]):
        out = np.empty((len(paths), points - 1, 2, 3), np.float32)
        out[:, :, 0] = paths[:, :-1]
        out[:, :, 1] = paths[:, 1:]
        path_of = np.broadcast_to(np.arange(len(paths))[:, None], ends.shape)
        if ends.all():
            return out.reshape(-1, 3), path_of.reshape(-1)
        return out[ends].reshape(-1, 3), path_of[ends]
    kept = np.flatnonzero(keep)
    path_of = kept // points
    joined = path_of[:-1] == path_of[1:]
    # Points as single 12-byte items: gathering them is several times faster than rows of 3.
    flat = np.ascontiguousarray(paths, np.float32).reshape(-1, 3).view(np.dtype((np.void, 12))).reshape(-1)
    kept_points = flat[kept]
    out = np.empty((int(np.count_nonzero(joined)), 2), flat.dtype)
    out[:, 0] = kept_points[:-1][joined]
    out[:, 1] = kept_points[1:][joined]
    return out.view(np.float32).reshape(-1, 3), path_of[:-1][joined]


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
    screen: Optional[screen_thinning.ScreenView] = None  # the view the paths were thinned for

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


def build_path_arrays(choice: PathChoice, polylines_of: Callable, budget: int = VERTEX_BUDGET,
                      screen: Optional[screen_thinning.ScreenView] = None):
    """The arrays of the paths `choice` draws within `budget` vertices.

    polylines_of(worlds, bodies, stride) -> float32 (len(worlds), len(bodies), points, 3): each
    world's paths of those bodies at every stride-th point and the last, NaN for bodies the world
    does not have and past a path shorter than the longest (Library.polylines). Only the bodies
    and worlds a tier may draw are read. screen: the view the paths are drawn in; vertices that
    add nothing visible in it are dropped (core.screen_thinning), so more worlds fit.
    """
    worlds = np.asarray(list(choice.worlds), dtype=np.int64)
    arrays = PathArrays(*[np.zeros((0, n), np.float32) for n in (3, 4, 3, 4)], worlds_total=len(worlds),
                        screen=screen)
    has_selected = choice.selected in set(worlds.tolist())
    if has_selected:
        paths = polylines_of([choice.selected], list(choice.bodies), 1)
        lines, path_of = joined_segments(paths, np.isfinite(paths[..., 0]))
        present = _present(choice.bodies, np.isfinite(paths[0, :, 0, 0]))
        arrays.selected = lines
        arrays.selected_colours = _rgba(choice)[np.repeat(np.asarray(choice.bodies, np.intp)[path_of], 2)]
        budget -= len(lines)
        arrays.paths_drawn += len(present)
        arrays.worlds.update([choice.selected] if present else [])
        arrays.drawn.append((choice.selected, present, 1))
    shades = {True: np.array([palette.matching(c) for c in choice.body_colours], np.float32).reshape(-1, 4),
              False: np.array([palette.rejected(c) for c in choice.body_colours], np.float32).reshape(-1, 4)}
    if has_selected:
        for table in shades.values():
            table[:, 3] *= DIMMED_ALPHA
    taken = {True: ([], []), False: ([], [])}
    # The first tier a world does not fit in is the last taken from.
    for positions, bodies, matched in _tiers(choice):
        tier = _Tier(worlds[positions], bodies, shades[matched], polylines_of, screen)
        stride = stride_to_fit(tier.points, len(positions) * len(bodies), budget)
        if screen is not None:
            stride = tier.finer_stride_on_screen(stride, budget)
        arrays.coarsest_stride = max(arrays.coarsest_stride, stride)
        for drawn, present, lines, colours in tier.take(stride, budget):
            budget -= len(lines)
            taken[matched][0].append(lines)
            taken[matched][1].append(colours)
            arrays.worlds.update(drawn)
            arrays.drawn.extend(zip(drawn, present, itertools.repeat(stride)))
            arrays.paths_drawn += sum(map(len, present))
        if tier.left_out:
            arrays.complete = False
            break
    arrays.others = _concatenate(taken[False][0] + taken[True][0], 3)
    arrays.other_colours = _concatenate(taken[False][1] + taken[True][1], 4)
    arrays.worlds_drawn = len(arrays.worlds)
    return arrays


class _Tier:
    """The paths of some bodies in worlds taken in order, read in chunks of about what the budget
    left holds."""

    def __init__(self, worlds, bodies, shades, polylines_of, screen):
        self.worlds, self.bodies, self.shades = worlds, bodies, shades
        self.polylines_of, self.screen = polylines_of, screen
        self.body_array = np.asarray(bodies, np.intp)
        # A path's points, estimated from the first world's.
        self.points = polylines_of(worlds[:1].tolist(), [], 1).shape[2]
        self.left_out = False

    def finer_stride_on_screen(self, stride, budget):
        """The finest stride down from `stride` at which the tier's paths, thinned on screen, are
        expected to fit `budget`: vertices counted on a sample of worlds (the first ones, spread over
        the library) of about SAMPLE_POINTS points, scaled to the tier."""
        def expected_vertices(s):
            count = max(1, min(len(self.worlds), SAMPLE_POINTS // max(1, len(self.bodies) * self.points // s)))
            paths = self.polylines_of(self.worlds[:count].tolist(), list(self.bodies), s)
            kept = screen_thinning.kept_on_screen(paths, self.screen).sum(axis=-1)
            return 2 * np.maximum(kept - 1, 0).sum() * len(self.worlds) / count

        if stride == 1 or expected_vertices(stride) > SAMPLE_MARGIN * budget:
            return stride
        # Vertices grow as the stride shrinks: find the finest that fits by bisection.
        fits, too_fine = stride, 0
        while fits - too_fine > 1:
            middle = (fits + too_fine) // 2
            if expected_vertices(middle) <= SAMPLE_MARGIN * budget:
                fits = middle
            else:
                too_fine = middle
        return fits

    def take(self, stride, budget):
        """Yield ([world that drew a segment], [its present bodies], line-list vertices, their
        colours) of chunks of worlds taken in order while they fit `budget`; sets
        left_out when a world did not fit."""
        per_world = max(1, len(self.bodies) * path_vertices(self.points, stride))
        start = 0
        while start < len(self.worlds):
            count = min(len(self.worlds) - start, int(budget / per_world * 1.1) + 1)
            chunk = self.worlds[start:start + count]
            paths = self.polylines_of(chunk.tolist(), list(self.bodies), stride)
            finite = np.isfinite(paths[..., 0])
            keep = finite if self.screen is None else screen_thinning.kept_on_screen(paths, self.screen)
            lines, path_of = joined_segments(paths, keep)
            segments = np.bincount(path_of // max(1, len(self.bodies)), minlength=len(chunk))
            fits = int(np.searchsorted(np.cumsum(2 * segments), budget, side="right"))
            end = 2 * int(segments[:fits].sum())
            drew = segments[:fits] > 0
            present = finite[:fits, :, 0][drew]
            if present.all():
                present = [self.bodies] * len(present)
            else:
                present = [_present(self.bodies, row) for row in present.tolist()]
            body_of = self.body_array[path_of[:end // 2] % max(1, len(self.bodies))]
            yield chunk[:fits][drew].tolist(), present, lines[:end], self.shades.take(np.repeat(body_of, 2), axis=0)
            budget -= end
            start += fits
            if fits < len(chunk):
                self.left_out = True
                return
            # Later chunks are sized by what these worlds took.
            per_world = max(1.0, end / max(1, fits))


def _present(bodies, mask):
    """The bodies of `bodies` whose mask entry is true, as a tuple."""
    return tuple(b for b, here in zip(bodies, mask) if here)


def selected_band_colours(count):
    """float32 (count, 4): the selected world's band, under its paths' own colours."""
    return np.broadcast_to(np.asarray(SELECTED_COLOR, np.float32), (count, 4))


def _rgba(choice):
    return np.array([tuple(c[:3]) + (1.0,) for c in choice.body_colours], np.float32).reshape(-1, 4)


def _concatenate(parts, width):
    return np.concatenate(parts) if parts else np.zeros((0, width), np.float32)
