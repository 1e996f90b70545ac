"""Boxes, pose parts and ranking settings (scene properties) turned into queries on the open library.

The evaluation itself is in core.library_query (no bpy); this module reads the properties, resolves
body names to the library's body indices, keeps the session's LibraryQuery in step with the open
view, and caches the ranking the panel shows. Boxes and pose parts are the goal's parts: they share
the scene's list (`scene.mwb.boxes`, told apart by `kind`), its order and its switches.
"""
import dataclasses
import traceback

import bpy
import numpy as np

from . import export, pose_parts, props
from .core import library_query as core_query
from .core import pose_target
from .core.session import SESSION

classes = ()


# Seconds between looks at a filling path index: the panel's count and the boxes' answer follow it.
INDEX_POLL_S = 0.5


def library_query():
    """The LibraryQuery of the open library (built on first use after opening), or None. Its
    index fills in the background; a timer follows the fill (poll_index_fill)."""
    view = SESSION.view
    if view is None:
        if SESSION.query is not None:
            SESSION.query.close()
        SESSION.query = None
        return None
    if SESSION.query is None or SESSION.query.view is not view:
        from . import _native
        if SESSION.query is not None:
            SESSION.query.close()
        SESSION.query = core_query.LibraryQuery(_native, view, background=True)
        follow_index_fill(SESSION.query)
    return SESSION.query


def follow_index_fill(lq):
    """Start the timer that follows `lq`'s index while it fills."""
    if lq.filling and not bpy.app.timers.is_registered(poll_index_fill):
        bpy.app.timers.register(poll_index_fill, first_interval=INDEX_POLL_S)


def poll_index_fill():
    """Timer while the path index fills: the boxes are evaluated again when worlds were indexed
    since their last answer, and the panels redraw with the count. Stops once every world is
    indexed (after one last evaluation) or the library is closed."""
    lq = SESSION.query
    if lq is None or lq.view is not SESSION.view:
        return None
    # Read before evaluating: a fill that ends meanwhile still gets its last evaluation next time.
    filling = lq.filling
    try:
        # Raises what stopped the fill; starts another for worlds that arrived after it ended.
        lq.sync()
        result = lq.result
        if result is not None and result.box_count and result.indexed != lq.indexed_count:
            refresh(bpy.context.scene)
        else:
            _tag_redraw()
    except Exception:
        # What stopped the fill is shown once; the index keeps the worlds indexed before it.
        traceback.print_exc()
        return None
    return INDEX_POLL_S if filling else None


def stop_index_poll():
    if bpy.app.timers.is_registered(poll_index_fill):
        bpy.app.timers.unregister(poll_index_fill)


def index_progress_text():
    """'Indexing 4,200 of 10,000 worlds' while the open library's index fills, else ""."""
    lq = SESSION.query
    if lq is None or lq.view is not SESSION.view:
        return ""
    return lq.progress_text()


# --- bodies -----------------------------------------------------------------------------------------

def deleted_objects(view):
    """Names of the library's bodies whose objects were deleted from this file since sampling (none
    when the file has no object of the library at all: a library opened elsewhere)."""
    names = set(view.body_names)
    present = {name for name in names if name in bpy.data.objects}
    return names - present if present else set()


def simulated_body_names(scene):
    """Names of the bodies the simulation moves: from the library if one is open (less those whose
    objects were deleted), else the scene."""
    view = SESSION.view
    if view is not None:
        gone = deleted_objects(view)
        # An object updated after sampling has a body per definition: name it once.
        return list(dict.fromkeys(view.body_names[i] for i in view.simulated_bodies()
                                  if view.body_names[i] not in gone))
    # No library yet: the objects as they would be exported, by the engine's own rule.
    return export.simulated_object_names(scene)


def _selected_names(context):
    return [ob.name for ob in (getattr(context, "selected_objects", None) or [])]


def _split_bodies(context, names, simulated):
    """(those of `names` the simulation moves, the rigid bodies among them it does not move)."""
    moving = set(simulated)
    view = SESSION.view
    bodies = set(view.body_names) if view is not None else {
        ob.name for ob in context.scene.objects if ob.rigid_body is not None}
    tested = [name for name in names if name in moving]
    return tested, [name for name in names if name in bodies and name not in moving]


def body_choice(context, names=None):
    """(tested, left_out) for a box or a ranking: of the objects named (default: the selected
    ones), the bodies the simulation moves, or every simulated body when none of them is; left_out
    names the rigid bodies among them that it does not move (passive or animated), whose paths
    never change from world to world."""
    simulated = simulated_body_names(context.scene)
    tested, left_out = _split_bodies(context, _selected_names(context) if names is None else names, simulated)
    return (tested or simulated), left_out


def pose_body_choice(context, names=None):
    """(posed, left_out) for a new pose part: of the objects named (default: the selected ones),
    those the simulation moves (none: no part can be made), and the rigid bodies among them it
    does not move."""
    return _split_bodies(context, _selected_names(context) if names is None else names,
                         simulated_body_names(context.scene))


def names_text(names, shown=3):
    """'Box0, Box1 and 4 more': a few names, for a line sized for a person."""
    if len(names) <= shown + 1:
        return ", ".join(names)
    return f"{', '.join(names[:shown])} and {len(names) - shown} more"


def new_pose_problem(context):
    """Why Add Pose cannot make a part of the selection now (one line), or ''."""
    posed, left_out = pose_body_choice(context)
    if posed:
        return ""
    if left_out:
        verb = "is" if len(left_out) == 1 else "are"
        return (f"To add a pose, select an object the simulation moves ({names_text(left_out)} {verb} passive "
                "or animated)")
    return "To add a pose, select objects the simulation moves"


def left_out_text(left_out):
    """The warning naming the objects a box leaves out, or ''."""
    if not left_out:
        return ""
    return f"Left out (passive or animated): {', '.join(left_out)}"


def default_body_names(context):
    """The selected objects the simulation moves, or every simulated body when none is selected."""
    return body_choice(context)[0]


def body_indices(names, view):
    """Library body indices of the objects named, sorted (every body of an object updated after
    sampling: a world has at most one of them); names it does not know are skipped."""
    wanted = set(names)
    return tuple(i for i, name in enumerate(view.body_names) if name in wanted)


def ranking_body_names(context):
    settings = context.scene.mwb
    if settings.rank_bodies == "SIMULATED":
        return simulated_body_names(context.scene)
    if settings.rank_bodies == "LISTED":
        return [item.name for item in settings.rank_body_names]
    if settings.rank_bodies == "BOXES":
        return boxes_body_names(context.scene)
    return default_body_names(context)


def boxes_body_names(scene):
    """The objects the enabled boxes and pose parts test, in list order, or every simulated body
    without any."""
    names = [item.name for box in scene.mwb.boxes if box.enabled for item in box.bodies]
    return list(dict.fromkeys(names)) or simulated_body_names(scene)


# --- boxes -------------------------------------------------------------------------------------------

def _time_window(part):
    # As the animator set it: a window that ends before it starts is the module's to refuse.
    return (part.time_start_s, part.time_end_s) if part.use_time_window else None


def spec_of(box, view):
    """The BoxSpec of a box property (PoseSpec of a pose part), or None when none of its bodies is
    in the library."""
    if box.kind == "POSE":
        return pose_spec_of(box, view)
    bodies = body_indices([item.name for item in box.bodies], view)
    if not bodies:
        return None
    return core_query.BoxSpec(
        view=np.array(box.view_matrix, dtype=np.float64).reshape(4, 4),
        projection=np.array(box.projection_matrix, dtype=np.float64).reshape(4, 4),
        size=tuple(box.region_size), rect=core_query.normalized_rect(*box.rect),
        negative=box.negative, bodies=bodies, time_window=_time_window(box), swept=box.swept)


def pose_spec_of(part, view):
    """The PoseSpec of a pose part, or None when none of its bodies is in the library or an As
    Posed part has no captured side."""
    bodies = body_indices([item.name for item in part.bodies], view)
    directions = pose_parts.directions(part)
    if not bodies or directions is None:
        return None
    axis, target = directions
    return core_query.PoseSpec(bodies=bodies, within_deg=part.within_deg, axis=axis, target=target,
                               negative=part.negative, longer_than_s=part.longer_than_s if part.negative else 0.0,
                               time_window=_time_window(part))


def drag_spec(view, view_matrix, projection_matrix, size, rect, negative, body_names):
    """The BoxSpec of a box being dragged (not stored yet), or None if it cannot be queried."""
    bodies = body_indices(body_names, view)
    if not bodies or core_query.too_small_text(rect):
        return None
    rect = core_query.normalized_rect(*rect)
    return core_query.BoxSpec(view=np.array(view_matrix, dtype=np.float64).reshape(4, 4),
                              projection=np.array(projection_matrix, dtype=np.float64).reshape(4, 4),
                              size=tuple(size), rect=rect, negative=negative, bodies=bodies)


def store_box(scene, view_matrix, projection_matrix, size, rect, negative, body_names):
    """Append a box drawn through a view (4x4 world-to-camera and camera-to-clip) to the scene."""
    box = scene.mwb.boxes.add()
    box.rect = core_query.normalized_rect(*rect)
    box.view_matrix = np.asarray(view_matrix, dtype=np.float64).ravel().tolist()
    box.projection_matrix = np.asarray(projection_matrix, dtype=np.float64).ravel().tolist()
    box.region_size = (int(size[0]), int(size[1]))
    # Set without the update callback: the caller evaluates once the box is complete.
    box["negative"] = bool(negative)
    for name in body_names:
        box.bodies.add().name = name
    scene.mwb.box_index = len(scene.mwb.boxes) - 1
    return box


def run_end_s(scene):
    """Seconds a world of the run lasts: the open library's duration, else the Duration setting,
    else the Rigid Body World's frame range."""
    view = SESSION.view
    if view is not None and view.library.header.parameters.duration_s > 0:
        return view.library.header.parameters.duration_s
    if scene.mwb.duration_s > 0:
        return scene.mwb.duration_s
    cache = scene.rigidbody_world.point_cache if scene.rigidbody_world is not None else scene
    return max(0.0, (cache.frame_end - cache.frame_start) / (scene.render.fps / scene.render.fps_base))


# A new positive pose part is tested over the run's last second: where a die has landed.
POSE_WINDOW_S = 1.0


def set_quietly(part, name, value):
    """Set a property without its update callback (the caller evaluates once, when done)."""
    prop = part.bl_rna.properties[name]
    part[name] = prop.enum_items[value].value if prop.type == "ENUM" else value


def store_pose(scene, body_names, mode=pose_target.UPRIGHT, negative=False):
    """Append a pose part testing the objects named (one part; As Posed captures the first one's
    side facing up now). A positive part gets the run's last second as its time window."""
    part = scene.mwb.boxes.add()
    set_quietly(part, "kind", "POSE")
    set_quietly(part, "pose_mode", mode)
    set_quietly(part, "negative", bool(negative))
    for name in body_names:
        part.bodies.add().name = name
    if mode == pose_target.AS_POSED:
        pose_parts.capture(part)
    if not negative:
        end = run_end_s(scene)
        set_quietly(part, "use_time_window", True)
        set_quietly(part, "time_start_s", max(0.0, end - POSE_WINDOW_S))
        set_quietly(part, "time_end_s", end)
    scene.mwb.box_index = len(scene.mwb.boxes) - 1
    return part


def enabled_parts(scene, view):
    """[(name, spec)]: the BoxSpecs and PoseSpecs of the enabled parts that test bodies of the
    library, in list order, each with the name the list gives it ("Box 3"); each one's `after`
    counts among them (a part met after a part left out has no order)."""
    boxes = scene.mwb.boxes
    specs = [spec_of(box, view) if box.enabled else None for box in boxes]
    afters = core_query.order_among([box.after_box for box in boxes], [spec is not None for spec in specs])
    kept = [(props.part_name(box, k), spec) for k, (box, spec) in enumerate(zip(boxes, specs)) if spec is not None]
    return [(name, dataclasses.replace(spec, after=after)) for (name, spec), after in zip(kept, afters)]


def enabled_specs(scene, view):
    """The specs of enabled_parts, without their names."""
    return [spec for _, spec in enabled_parts(scene, view)]


def remove_box(scene, index):
    """Delete box `index`: boxes met after it lose their order, the later ones keep theirs."""
    boxes = scene.mwb.boxes
    afters = core_query.order_after_removing([box.after_box for box in boxes], index)
    boxes.remove(index)
    for box, after in zip(boxes, afters):
        # Without the update callback: the caller evaluates once, after the removal.
        box["after_box"] = after


def refresh(scene, extra=None):
    """Evaluate the scene's enabled boxes and poses (plus `extra`, a box being dragged) on the open
    library.

    Updates the view's match flags (drawing rebuilds from them) and returns the Matches, or None
    without a library. A part the module refuses as set (a time window that ends before it starts)
    is named in SESSION.goal_problem, and until it is mended no part filters the worlds.
    """
    lq = library_query()
    SESSION.goal_problem = ""
    if lq is None:
        return None
    parts = enabled_parts(scene, lq.view)
    if extra is not None:
        parts.append(("The box being drawn", extra))
    try:
        result = lq.evaluate([spec for _, spec in parts], [name for name, _ in parts]) if parts else lq.clear()
    except ValueError as error:
        SESSION.goal_problem = str(error)
        result = lq.clear()
    follow_index_fill(lq)
    _tag_redraw()
    return result


def _tag_redraw():
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else []):
        for area in window.screen.areas:
            if area.type in ("VIEW_3D", "PROPERTIES"):
                area.tag_redraw()


def match_text():
    view = SESSION.view
    if view is None:
        return ""
    return core_query.match_count_text(int(view.matching.sum()), len(view.world_indices))


# --- ranking ------------------------------------------------------------------------------------------

class RankingCache:
    """The last ranking, recomputed only when the view's data or matches or the settings change."""

    def __init__(self):
        self._key = None
        self.ids = np.zeros(0, np.int64)
        self.values = np.zeros(0)
        self.position = {}   # world index -> row in the ranking
        self.decimals = 2    # of the value column: enough to tell the worlds apart

    def clear(self):
        self.__init__()

    def get(self, context):
        lq = library_query()
        if lq is None:
            return self
        settings = context.scene.mwb
        bodies = body_indices(ranking_body_names(context), lq.view)
        result_id = id(lq.result) if lq.result is not None else 0
        # While the index fills, the ranking grows with it.
        key = (id(lq.view), lq.view.version, result_id, lq.indexed_count, settings.rank_metric,
               settings.rank_combine, settings.rank_descending, bodies)
        if key != self._key:
            self.ids, self.values = lq.rank(settings.rank_metric, bodies, settings.rank_combine.lower(),
                                            settings.rank_descending)
            self.position = {int(w): k for k, w in enumerate(self.ids)}
            self.decimals = core_query.decimals_telling_apart(self.values)
            self._key = key
        return self


RANKING = RankingCache()


def _metric_units():
    from . import _native
    return {m.name: m.unit for m in _native.ranking_metrics()}


METRIC_UNITS = _metric_units()


def format_metric(metric, value, box_count=0, decimals=2):
    """A metric's value as the ranking's value column shows it, by the unit the module gives the
    metric, seconds and metres with `decimals`; boxes met read "2 of 3" (the column's header names
    the metric)."""
    unit = METRIC_UNITS.get(metric)
    if unit == "rad":
        return f"{np.degrees(value):.1f}\u00b0"
    if unit in ("s", "m"):
        return f"{value:.{decimals}f} {unit}"
    if unit == "hits":
        return f"{int(round(value))} hits"
    return f"{int(round(value))} of {box_count}"
