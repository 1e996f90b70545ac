"""Box queries and rankings over an open library, without bpy.

A `LibraryQuery` owns the native PathIndex of one LibraryView. The add-on describes boxes as
plain `BoxSpec` values (read from scene properties by the bpy side) and gets back per-world flags
in the view's order. The index is incremental: `sync()` indexes only worlds not indexed yet, so
worlds streaming in while sampling cost only their own trees. In the add-on a large backlog (a
library just opened) fills on a background thread (`IndexFill`): the paths are drawn meanwhile,
and queries and rankings answer for the worlds indexed so far (a world not indexed yet matches no
box and is not ranked).
"""
import os
import threading
from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

import numpy as np

# The ranking metric counting the goal's parts (boxes and poses) each world meets (the module's
# catalog names and labels every metric, see _native.ranking_metrics()); then every world is
# listed, not only the matching ones.
BOXES_MET = "boxes_met"
# Names metrics had before; files and scripts that use them keep working.
OLD_METRIC_NAMES = {"constraints_satisfied": BOXES_MET}


def metric_name(name):
    """The current name of a ranking metric given by its current or an earlier name."""
    return OLD_METRIC_NAMES.get(name, name)


@dataclass(frozen=True)
class BoxSpec:
    """A screen rectangle seen through the view it was drawn in.

    view, projection: (4, 4) row-major world-to-camera and camera-to-clip matrices (OpenGL);
    size: region (width, height) in pixels; rect: (x0, y0, x1, y1) pixels from the region's
    bottom-left; bodies: scene body indices; time_window: (start_s, end_s) or None; after: the
    position, in the same list of boxes, of the box this one is met after (-1: no order).
    """
    view: np.ndarray
    projection: np.ndarray
    size: Tuple[int, int]
    rect: Tuple[float, float, float, float]
    negative: bool = False
    bodies: Tuple[int, ...] = ()
    time_window: Optional[Tuple[float, float]] = None
    swept: bool = False
    after: int = -1


@dataclass(frozen=True)
class PoseSpec:
    """A pose part of a goal: each body's own `axis` (body frame) pointing within `within_deg` of
    the world direction `target` ("upright": the object's local Z towards world +Z).

    A positive part is met when every body keeps within the tolerance throughout the time window
    (or the whole path); a negative one when no body stays within for longer than
    `longer_than_s` (0: for any moment). time_window and after as for a BoxSpec; it sits in the
    same list as the boxes.
    """
    bodies: Tuple[int, ...]
    within_deg: float
    axis: Tuple[float, float, float] = (0.0, 0.0, 1.0)
    target: Tuple[float, float, float] = (0.0, 0.0, 1.0)
    negative: bool = False
    longer_than_s: float = 0.0
    time_window: Optional[Tuple[float, float]] = None
    after: int = -1


def normalized_rect(x0, y0, x1, y1):
    """(min x, min y, max x, max y) of a rectangle dragged in any direction."""
    return min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1)


def decimals_telling_apart(values, least=2, most=4):
    """Decimals (`least` to `most`) at which values that differ at `most` decimals print
    differently: a ranking's neighbours are told apart, whatever their size."""
    distinct = len(np.unique(np.round(np.asarray(values, dtype=float), most)))
    for decimals in range(least, most):
        if len(np.unique(np.round(np.asarray(values, dtype=float), decimals))) == distinct:
            return decimals
    return most


# A rectangle narrower or lower than this (region pixels) is a click, not a box.
MIN_BOX_PX = 3


def too_small_text(rect):
    """Why the rectangle (x0, y0, x1, y1, corners in any order) is no box, or '' when it is one."""
    x0, y0, x1, y1 = normalized_rect(*rect)
    if x1 - x0 >= MIN_BOX_PX and y1 - y0 >= MIN_BOX_PX:
        return ""
    return f"The box was too small ({x1 - x0:.0f}×{y1 - y0:.0f} px): drag at least {MIN_BOX_PX} px each way"


def order_among(afters, kept):
    """The order of the boxes that are passed on, by their positions in the passed list.

    afters: per box of the whole list, the position of the box it is met after (-1: none); kept:
    per box, whether it is passed on (enabled, and testing bodies the library has). Returns the
    `after` of each kept box, in order, counted among the kept boxes; a box whose predecessor is
    not kept has no order.
    """
    position = {}
    for k, keep in enumerate(kept):
        if keep:
            position[k] = len(position)
    return [position.get(afters[k], -1) for k in position]


def native_box(spec, native=None):
    """The module's QueryBox of a BoxSpec or PoseSpec (the module validates it: ValueError says
    what is wrong); its `after` counts in the list it is queried with."""
    if native is None:
        from .. import _native as native
    if isinstance(spec, PoseSpec):
        return native.pose_part(
            bodies=list(spec.bodies), within_deg=float(spec.within_deg),
            axis=tuple(float(v) for v in spec.axis), target=tuple(float(v) for v in spec.target),
            negative=bool(spec.negative), longer_than_s=float(spec.longer_than_s),
            time_window=spec.time_window, after=int(spec.after))
    return native.QueryBox(
        np.asarray(spec.view, dtype=np.float64).reshape(4, 4),
        np.asarray(spec.projection, dtype=np.float64).reshape(4, 4),
        (float(spec.size[0]), float(spec.size[1])), tuple(float(v) for v in spec.rect),
        negative=bool(spec.negative), bodies=list(spec.bodies),
        time_window=spec.time_window, swept=bool(spec.swept), after=int(spec.after))


def part_noun(spec):
    """What the goal calls a part in its messages: 'box' or 'pose part'."""
    return "pose part" if isinstance(spec, PoseSpec) else "box"


def native_parts(specs, native=None, names=None):
    """The module's QueryBoxes of BoxSpecs and PoseSpecs; ValueError names the part refused, by
    `names` (what the caller calls each part, e.g. "Box 3") or else by its place in the list
    ("pose part 2 has a tolerance ...")."""
    parts = []
    for k, spec in enumerate(specs):
        try:
            parts.append(native_box(spec, native))
        except ValueError as error:
            name = names[k] if names is not None else f"{part_noun(spec)} {k + 1}"
            raise ValueError(f"{name} {error}") from None
    return parts


def order_after_removing(afters, removed):
    """The afters (as in order_among) of the boxes left once box `removed` is deleted: later boxes
    move up one place, and a box met after the deleted one has no order any more."""
    return [-1 if a == removed else a - (a > removed) for k, a in enumerate(afters) if k != removed]


def closes_order_cycle(afters, box, candidate, native=None):
    """Whether making `box` met after `candidate` would order a part after itself, directly or
    through the parts `candidate` is met after (afters: as in order_among). The module's goal
    order decides, as it does for the goal itself (query/GoalScore.h)."""
    if native is None:
        from .. import _native as native
    if not 0 <= candidate < len(afters):
        return False
    trial = list(afters)
    trial[box] = candidate
    try:
        native.goal_order(trial)
    except ValueError:
        return True
    return False


def match_count_text(matching, total):
    """The panel's line, e.g. '37 of 1,500 worlds match'."""
    noun = "world matches" if total == 1 else "worlds match"
    return f"{matching:,} of {total:,} {noun}"


def index_progress_text(indexed, total):
    """The panel's line while the path index fills, e.g. 'Indexing 4,200 of 10,000 worlds'."""
    return f"Indexing {indexed:,} of {total:,} worlds"


def world_label_text(world, rest_s, parts_met=0, part_count=0):
    """The viewport's one line naming the previewed world: "World 216 · 5.47 s · 3 of 3 parts"
    (the goal's parts, boxes and poses, only while some are enabled)."""
    fields = [f"World {world}", f"{rest_s:.2f} s"]
    if part_count:
        fields.append(f"{parts_met} of {part_count} {'part' if part_count == 1 else 'parts'}")
    return " \u00b7 ".join(fields)


@dataclass
class Matches:
    """Which worlds meet the goal's parts after one evaluation, in the LibraryView's (file) order."""
    matching: np.ndarray          # bool (worlds,)
    boxes_satisfied: np.ndarray   # uint32 (worlds,)
    box_count: int
    indexed: int = 0              # worlds indexed when it was evaluated (the others match nothing)


# Worlds one step of the background fill indexes: a step holds the library's read lock (a poll for
# new worlds waits for it) for a few milliseconds.
FILL_STEP_WORLDS = 256
# A backlog this small is indexed before a query answers (a few milliseconds), so worlds streaming
# in while sampling match at once; a larger one fills in the background.
FOREGROUND_WORLDS = 256


class IndexFill:
    """Indexes a library's worlds into a PathIndex on a background thread, FILL_STEP_WORLDS at a
    time in file order, until none is left. The native calls release the GIL, and queries on the
    same index meanwhile see every world indexed so far."""

    def __init__(self, index, library, threads):
        self.index = index
        self.error = None
        self._library = library
        self._threads = threads
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="mwb-index-fill", daemon=True)
        self._thread.start()

    def _run(self):
        try:
            while not self._stop.is_set() and self._step():
                pass
        except Exception as error:  # kept for the main thread: LibraryQuery.sync raises it
            self.error = error

    def _step(self):
        """Index the next worlds not indexed yet; returns how many (0: none was left)."""
        return self.index.add_library(self._library, threads=self._threads, limit=FILL_STEP_WORLDS)

    @property
    def stopping(self):
        return self._stop.is_set()

    @property
    def running(self):
        return self._thread.is_alive()

    def stop(self):
        """Stop after the step under way and wait for it."""
        self._stop.set()
        self._thread.join()


class LibraryQuery:
    """The path index of one LibraryView, the last evaluation and rankings over it.

    Bodies absent from a world (added elsewhere or later, or removed) never enter a box (the
    index sees no path for them); the index ranks each world over the ranked bodies it has and
    leaves out a world with none of them.
    """

    def __init__(self, native, view, background=False):
        """background: fill the index on a background thread (the add-on); otherwise every world is
        indexed before a query or ranking answers (the command line, scripts)."""
        self.native = native
        self.view = view
        self.background = background
        self.generation = 0
        self.result = None
        self._boxes = []   # the module's QueryBoxes evaluated last (what boxes_met counts)
        self._fill = None
        self._new_index()
        self.sync()

    def _new_index(self):
        # The view's scene, parsed once when it read the library's scene (revision).
        self.index = self.native.PathIndex(self.native.body_bounding_radii(self.view.scene))
        self.scene_revision = self.view.scene_revision

    @property
    def indexed_count(self):
        """Worlds the index holds (queries and rankings see these)."""
        return self.index.world_count

    @property
    def filling(self):
        """Whether worlds of the view are still waiting to be indexed."""
        return self.index.world_count < len(self.view.world_indices)

    def progress_text(self):
        """The panel's line while the index fills ("" once every world is indexed)."""
        if not self.filling:
            return ""
        return index_progress_text(self.indexed_count, len(self.view.world_indices))

    def sync(self):
        """Index the view's worlds that are not indexed yet (GIL released); returns how many were
        indexed here. With `background`, a backlog of more than FOREGROUND_WORLDS is left to the
        background fill (started if it is not running) and this returns at once.

        Bodies added to the library since the index was built need an index with their radii,
        so then every world is indexed anew. Raises what stopped the background fill, if anything.
        """
        if self._fill is not None and self._fill.error is not None:
            error, self._fill = self._fill.error, None
            raise error
        if self.scene_revision != self.view.scene_revision:
            self.close()
            self._new_index()
        backlog = len(self.view.world_indices) - self.index.world_count
        if backlog <= 0 or (self._fill is not None and self._fill.running):
            return 0
        if not self.background or backlog <= FOREGROUND_WORLDS:
            return self.index.add_library(self.view.library)
        # One core stays free for Blender's UI.
        self._fill = IndexFill(self.index, self.view.library, threads=max(1, (os.cpu_count() or 1) - 1))
        return 0

    def complete(self):
        """Index every world of the view now, on all cores (a background fill stops first); returns
        how many were indexed here."""
        self.close()
        if self.scene_revision != self.view.scene_revision:
            self._new_index()
        return self.index.add_library(self.view.library)

    def close(self):
        """Stop the background fill, if one runs (worlds indexed so far stay)."""
        if self._fill is not None:
            self._fill.stop()
            self._fill = None

    def native_box(self, spec):
        """The module's QueryBox of a BoxSpec or PoseSpec; its `after` counts in the list it is queried
        with."""
        return native_box(spec, self.native)

    def evaluate(self, specs: Sequence[BoxSpec], names=None):
        """Run the boxes and pose parts (AND; an ordered part counts when met after its predecessor)
        and store the match flags in the view. Returns the Matches. Raises ValueError for a part the
        module refuses (named by `names`, see native_parts) or an ordering cycle.

        Each evaluation posts a new generation first, so a query still running for an older box
        set (from another thread) stops early instead of finishing work nobody will read. While
        the index fills, the answer is that of the worlds indexed so far; the others match nothing.
        """
        self.sync()
        file_order = np.asarray(self.view.world_indices, dtype=np.uint64)
        boxes = native_parts(specs, self.native, names)
        self._boxes = boxes
        self.generation += 1
        self.index.post_generation(self.generation)
        raw = self.index.query(boxes, generation=self.generation)
        # The index answers in world-index order; the view (and drawing) uses file order.
        ids = np.asarray(raw.world_indices, dtype=np.uint64)
        satisfied_sorted = np.asarray(raw.boxes_satisfied, dtype=np.uint32)
        satisfied = np.zeros(len(file_order), dtype=np.uint32)
        if len(ids):
            where = np.minimum(np.searchsorted(ids, file_order), len(ids) - 1)
            known = ids[where] == file_order
            satisfied[known] = satisfied_sorted[where[known]]
        matching = np.isin(file_order, np.asarray(raw.matching, dtype=np.uint64))
        self.view.set_matching(matching)
        self.result = Matches(matching, satisfied, len(boxes), indexed=len(ids))
        return self.result

    def clear(self):
        """No boxes: every world matches."""
        self._boxes = []
        self.view.set_matching(np.ones(len(self.view.world_indices), dtype=bool))
        self.result = Matches(self.view.matching.copy(),
                                  np.zeros(len(self.view.world_indices), dtype=np.uint32), 0,
                                  indexed=self.indexed_count)
        return self.result

    def rank(self, metric, bodies, combine="sum", descending=False, goals=None):
        """Worlds and values sorted by a metric over bodies: (world ids int64, values float64).

        Per-body metrics list the matching worlds only; BOXES_MET lists every world with its
        count of boxes met (ties keep world-index order). While the index fills, per-body metrics
        list the worlds indexed so far.
        """
        self.sync()
        if metric_name(metric) == BOXES_MET:
            # Counted by the index, as its queries count them, over the boxes evaluated last.
            ranking = self.index.rank(BOXES_MET, [], descending=descending, boxes=self._boxes)
            return ranking.world_indices.astype(np.int64), ranking.values
        if not bodies:
            return np.zeros(0, np.int64), np.zeros(0)
        only = [int(w) for w, m in zip(self.view.world_indices, self.view.matching) if m]
        if metric == "orientation_to_goal_rad" and goals is None:
            # The object's unrotated pose is the goal: 'land upright' for a model built upright.
            goals = [(1.0, 0.0, 0.0, 0.0)] * len(bodies)
        ranking = self.index.rank(metric, list(bodies), combine=combine, descending=descending, only=only, goals=goals)
        return ranking.world_indices.astype(np.int64), ranking.values
