"""Properties saved with the .blend: per-object variation ranges and per-scene sampling and
browsing state. Runtime objects (open library, engine process) live in core.session."""
import math

import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, IntVectorProperty, PointerProperty, StringProperty)

from . import _native, compat, pose_parts
from .core import pose_target, reactions

# The run settings' defaults are the engine's (library/RunSettings.h), not copies of them.
_RUN_DEFAULTS = _native.RunSettings()


def _vector(name, subtype, description, unit="NONE"):
    return FloatVectorProperty(name=name, size=3, subtype=subtype, unit=unit, description=description)


# Ranges are stored as min and max offsets (what the scene JSON and files saved before the ± fields
# hold); the panel shows each range as ± around the object's current value, a view of min and max.

def _half_range(low, high, to_shown=1.0):
    """A FloatVectorProperty reading and writing a min/max pair as its half width (±), keeping
    the centre; `to_shown` scales stored units to shown ones (rad/s to °/s)."""

    def get(self):
        return [(b - a) / 2 * to_shown for a, b in zip(getattr(self, low), getattr(self, high))]

    def set(self, values):
        lows, highs = list(getattr(self, low)), list(getattr(self, high))
        for k, value in enumerate(values):
            centre = (lows[k] + highs[k]) / 2
            half = max(0.0, value / to_shown)
            lows[k], highs[k] = centre - half, centre + half
        setattr(self, low, lows)
        setattr(self, high, highs)

    return get, set


def _scaled(name, to_shown=1.0):
    """A FloatVectorProperty reading and writing a stored vector in shown units."""

    def get(self):
        return [v * to_shown for v in getattr(self, name)]

    def set(self, values):
        setattr(self, name, [v / to_shown for v in values])

    return get, set


DEG_PER_RAD = 180.0 / math.pi


def _plus_minus(name, low, high, subtype, unit, description, to_shown=1.0):
    get, set = _half_range(low, high, to_shown)
    return FloatVectorProperty(name=name, size=3, subtype=subtype, unit=unit, min=0.0, get=get, set=set,
                               description=description)


class MWB_ObjectVariation(bpy.types.PropertyGroup):
    """Uniform ranges added to the object's initial state, per sampled world."""
    location_min: _vector("Location Min", "TRANSLATION", "Lowest offset added to the initial location", "LENGTH")
    location_max: _vector("Location Max", "TRANSLATION", "Highest offset added to the initial location", "LENGTH")
    rotation_min: _vector("Rotation Min", "EULER", "Lowest XYZ Euler rotation added to the initial pose")
    rotation_max: _vector("Rotation Max", "EULER", "Highest XYZ Euler rotation added to the initial pose")
    linear_velocity_min: _vector("Velocity Min", "VELOCITY", "Lowest initial linear velocity (m/s, world)",
                                 "VELOCITY")
    linear_velocity_max: _vector("Velocity Max", "VELOCITY", "Highest initial linear velocity (m/s, world)",
                                 "VELOCITY")
    angular_velocity_min: _vector("Angular Velocity Min", "XYZ", "Lowest initial angular velocity (rad/s, world)")
    angular_velocity_max: _vector("Angular Velocity Max", "XYZ", "Highest initial angular velocity (rad/s, world)")
    # The same ranges as the panel shows them.
    location_pm: _plus_minus("Location ±", "location_min", "location_max", "TRANSLATION", "LENGTH",
                             "How far each world may start from the object's location, either way")
    rotation_pm: _plus_minus("Rotation ±", "rotation_min", "rotation_max", "EULER", "ROTATION",
                             "How far each world may turn the object's starting rotation, either way (XYZ Euler)")
    linear_velocity_pm: _plus_minus("Velocity ±", "linear_velocity_min", "linear_velocity_max", "VELOCITY",
                                    "VELOCITY", "Starting velocity either way around the object's own (world axes)")
    angular_velocity_pm: _plus_minus("Spin ±", "angular_velocity_min", "angular_velocity_max", "XYZ", "NONE",
                                     "Starting angular velocity either way around the object's own, degrees per "
                                     "second (world axes)", DEG_PER_RAD)
    angular_velocity_min_deg: FloatVectorProperty(
        name="Spin Min", size=3, subtype="XYZ", get=_scaled("angular_velocity_min", DEG_PER_RAD)[0],
        set=_scaled("angular_velocity_min", DEG_PER_RAD)[1],
        description="Lowest starting angular velocity added, degrees per second (world axes)")
    angular_velocity_max_deg: FloatVectorProperty(
        name="Spin Max", size=3, subtype="XYZ", get=_scaled("angular_velocity_max", DEG_PER_RAD)[0],
        set=_scaled("angular_velocity_max", DEG_PER_RAD)[1],
        description="Highest starting angular velocity added, degrees per second (world axes)")
    show_min_max: BoolProperty(name="Advanced", default=False,
                               description="Enter each range as its lowest and highest offset (uneven ranges)")


class MWB_WorldItem(bpy.types.PropertyGroup):
    """One stored world as listed in the panel."""
    world_index: IntProperty(name="World")
    rest_s: FloatProperty(name="Rest", description="Time until the last body came to rest", unit="TIME_ABSOLUTE")
    collisions: IntProperty(name="Collisions", description="Collisions of the simulated bodies")
    travel_m: FloatProperty(name="Travel", description="Summed path length of the simulated bodies", unit="LENGTH")


class MWB_SavedTransform(bpy.types.PropertyGroup):
    """An object's own transform and display from before previewing, to put back when the preview ends."""
    target: PointerProperty(type=bpy.types.Object)
    matrix_basis: FloatVectorProperty(size=16)
    display_type: StringProperty(description="The object's display type ('' in files saved before it was kept)")
    restored: BoolProperty(default=False, description="Already at its own transform (its body is not in the "
                                                      "previewed world), which the user may change")


class MWB_LibraryItem(bpy.types.PropertyGroup):
    """A library sampled from this .blend: a new one starts whenever the scene or the run settings
    change, and the old ones are kept to switch back to."""
    path: StringProperty(name="Library", subtype="FILE_PATH", options=compat.BLEND_RELATIVE_PATH,
                         description="The library file (relative to the .blend)")
    interrupted_first: IntProperty(default=-1, description="First world of a run cancelled before its end; -1: none")
    interrupted_end: IntProperty(default=-1, description="End (exclusive) of that run")


def _on_library_index(self, context):
    # Choosing a library in the list makes it the one Sample writes to and the one browsed.
    if 0 <= self.library_index < len(self.libraries):
        self.library_path = self.libraries[self.library_index].path
        reactions.notify(reactions.LIBRARY_CHOSEN, context.scene)
    _tag_redraw(self, context)


def _on_world_list_index(self, context):
    # Selecting a row previews that world.
    if 0 <= self.world_list_index < len(self.worlds):
        self.selected_world = self.worlds[self.world_list_index].world_index
        reactions.notify(reactions.WORLD_SELECTED, context.scene)
    for area in (context.screen.areas if context.screen else []):
        area.tag_redraw()


def _tag_redraw(self, context):
    for area in (context.screen.areas if context.screen else []):
        area.tag_redraw()


def _on_box_change(self, context):
    # Any edit of a box changes which worlds match.
    reactions.notify(reactions.BOXES_CHANGED, context.scene)


class MWB_BodyName(bpy.types.PropertyGroup):
    """A scene body referred to by its object name (`name`), as the library's scene knows it."""


def _box_position(box):
    """The position of a box property in its scene's list."""
    boxes = box.id_data.mwb.boxes
    return next(k for k, other in enumerate(boxes) if other == box)


def part_name(part, index):
    """A goal part as the list and the After menu name it, by its position: 'Box 1', 'Pose 2'."""
    return f"{'Pose' if part.kind == 'POSE' else 'Box'} {index + 1}"


# Dynamic enum items must stay referenced while Blender shows them.
_AFTER_ITEMS = []


def _after_items(self, context):
    """'None' and every other part (box or pose) that this one can be met after without closing a
    cycle; an item's number is the part's position + 1."""
    from .core.library_query import closes_order_cycle
    boxes = self.id_data.mwb.boxes
    here = _box_position(self)
    afters = [box.after_box for box in boxes]
    items = [("NONE", "None", "Met at any time", 0)]
    for k in range(len(boxes)):
        if not closes_order_cycle(afters, here, k):
            name = part_name(boxes[k], k)
            items.append((str(k), name, f"Counts only when met after {name.lower()} is", k + 1))
    _AFTER_ITEMS[:] = items
    return items


def _get_after(self):
    return self.after_box + 1


def _set_after(self, value):
    from .core.library_query import closes_order_cycle
    after = value - 1
    if after >= 0 and closes_order_cycle([box.after_box for box in self.id_data.mwb.boxes],
                                         _box_position(self), after):
        return
    self.after_box = after


def _on_pose_mode(self, context):
    # Choosing As Posed on a part that never captured a pose captures the current one.
    if self.pose_mode == pose_target.AS_POSED and not any(self.pose_captured_axis):
        pose_parts.capture(self)
    _on_box_change(self, context)


_DIRECTION_ITEMS = [(name, label, "", k) for k, (name, label, _) in enumerate(pose_target.DIRECTIONS)]
POSE_MODE_ITEMS = [
    (pose_target.UPRIGHT, "Upright", "The object's local +Z towards world up", 0),
    (pose_target.AXIS, "Axis", "One of the object's own axes towards a world direction", 1),
    (pose_target.AS_POSED, "As Posed", "The side of the object that faces up when the pose is captured stays up "
                                       "(Use Current Pose captures it again)", 2)]


class MWB_QueryBox(bpy.types.PropertyGroup):
    """A part of the goal: a box drawn in a 3D viewport, or a pose of objects.

    A box is the rectangle plus the view it was drawn through: the matrices and the region size at
    drawing time make it a fixed frustum in world space, whatever the viewport shows later. A pose
    part holds an axis of each of its objects within a tolerance of a world direction. Both kinds
    share one list, so their order (After), switches and saving work alike.
    """
    kind: EnumProperty(name="Kind", default="BOX", update=_on_box_change,
                       items=[("BOX", "Box", "A box drawn through a view: the objects' paths enter it or "
                                             "stay out of it", 0),
                              ("POSE", "Pose", "An axis of each object held towards a world direction", 1)])
    rect: FloatVectorProperty(name="Rectangle", size=4,
                              description="x0, y0, x1, y1 in region pixels from the bottom-left")
    view_matrix: FloatVectorProperty(name="View Matrix", size=16, description="World to camera, row-major")
    projection_matrix: FloatVectorProperty(name="Projection Matrix", size=16,
                                           description="Camera to clip (OpenGL), row-major")
    region_size: IntVectorProperty(name="Region Size", size=2, description="Viewport width and height, pixels")
    enabled: BoolProperty(name="Enabled", default=True, update=_on_box_change,
                          description="Use this part in the query")
    negative: BoolProperty(name="Negative", default=False, update=_on_box_change,
                           description="Keep worlds whose paths stay out of the box, or whose objects never hold "
                                       "the pose (longer than Longer Than); else: enter the box, hold the pose")
    bodies: CollectionProperty(type=MWB_BodyName, description="Bodies whose paths the box tests")
    use_time_window: BoolProperty(name="Time Window", default=False, update=_on_box_change,
                                  description="Test only the part of the paths between two times")
    time_start_s: FloatProperty(name="From", default=0.0, min=0.0, unit="TIME_ABSOLUTE", update=_on_box_change,
                                description="Start of the time window, seconds of simulated time")
    time_end_s: FloatProperty(name="To", default=1.0, min=0.0, unit="TIME_ABSOLUTE", update=_on_box_change,
                              description="End of the time window, seconds of simulated time")
    swept: BoolProperty(name="Swept", default=False, update=_on_box_change,
                        description="Test the bodies' bounding spheres along the path, not only their origins")
    after_box: IntProperty(name="After Box", default=-1, min=-1, update=_on_box_change,
                           description="Position in the list of the box this one must be met after; -1: any time")
    # The list's choice of after_box (whose update evaluates the boxes again).
    after: EnumProperty(name="After", items=_after_items, get=_get_after, set=_set_after,
                        description="Count this part only when its bodies meet it after the chosen part is met "
                                    "(a disabled predecessor leaves it unordered)")
    # Pose parts
    pose_mode: EnumProperty(name="Pose", items=POSE_MODE_ITEMS, default=pose_target.UPRIGHT, update=_on_pose_mode,
                            description="Which way the objects should face")
    pose_axis: EnumProperty(name="Object Axis", items=_DIRECTION_ITEMS, default="POS_Z", update=_on_box_change,
                            description="The object's own axis (local) that the part turns")
    pose_direction: EnumProperty(name="World Direction", items=_DIRECTION_ITEMS, default="POS_Z",
                                 update=_on_box_change, description="The world direction the object's axis faces")
    pose_captured_axis: FloatVectorProperty(
        name="Captured Side", size=3, update=_on_box_change,
        description="As Posed: the side of the object that faced up when captured, in its own axes")
    within_deg: FloatProperty(name="Within", default=15.0, min=0.1, max=179.9, precision=1, update=_on_box_change,
                              description="Tolerance: how many degrees the object's axis may turn away from the "
                                          "direction")
    longer_than_s: FloatProperty(name="Longer Than", default=0.0, min=0.0, unit="TIME_ABSOLUTE",
                                 update=_on_box_change,
                                 description="Negative pose: reject worlds where an object holds the pose for longer "
                                             "than this; 0: for any moment")


def _rank_metric_items():
    # The module's catalog, in its order: a saved choice is stored by its position, and the count
    # of goal parts (once "constraints_satisfied", now "boxes_met") keeps its place at the end.
    return [(m.name, m.label, f"{m.help} ({m.unit})") for m in _native.ranking_metrics()]


RANK_METRICS = _rank_metric_items()


class MWB_SceneSettings(bpy.types.PropertyGroup):
    # Sampling
    library_path: StringProperty(
        name="Library", subtype="FILE_PATH", options=compat.BLEND_RELATIVE_PATH,
        description="Library file (.mwb) the worlds are written to; empty: <blend name>.mwb next to the .blend")
    world_count: IntProperty(name="Worlds", default=100, min=1, soft_max=10000,
                             description="Worlds to add per press of Sample")
    seed: IntProperty(name="Seed", default=_RUN_DEFAULTS.seed, min=0,
                      description="Base seed: a world is a function of seed and index")
    stop_at_rest: BoolProperty(name="Until Rest", default=_RUN_DEFAULTS.stop_at_rest,
                               description="End a world when every body has rested for a while")
    duration_s: FloatProperty(name="Duration", default=max(0.0, _RUN_DEFAULTS.duration_s), min=0.0,
                              unit="TIME_ABSOLUTE",
                              description="Simulated seconds per world; 0: the rigid body world's frame range")
    alpha: FloatProperty(name="Perturbation", default=_RUN_DEFAULTS.alpha, min=0.0, max=0.4,
                         description="Strength of the random change at each impact (alpha, fraction of |dv|)")
    position_error_mm: FloatProperty(name="Position Error", default=_RUN_DEFAULTS.position_error_m * 1000.0,
                                     min=0.01, soft_max=10.0,
                                     description="Largest stored position error, millimetres")
    rotation_error_deg: FloatProperty(name="Rotation Error", default=_RUN_DEFAULTS.rotation_error_deg,
                                      min=0.01, soft_max=5.0,
                                      description="Largest stored rotation error, degrees")
    threads: IntProperty(name="Threads", default=0, min=0, description="Engine threads; 0: all cores")
    libraries: CollectionProperty(type=MWB_LibraryItem)
    library_index: IntProperty(name="Library", default=-1, update=_on_library_index)
    # Browsing
    worlds: CollectionProperty(type=MWB_WorldItem)
    world_list_index: IntProperty(name="World", default=-1, update=_on_world_list_index)
    selected_world: IntProperty(name="Selected World", default=-1,
                                description="Index of the world being previewed; -1: none")
    show_paths: BoolProperty(name="Show Paths", default=True, update=_tag_redraw)
    path_bodies: EnumProperty(
        name="Paths Of", default="ACTIVE", update=_tag_redraw,
        items=[("ACTIVE", "Simulated Bodies", "Paths of every body the simulation moves"),
               ("SELECTED", "Selected Objects", "Paths of the selected objects only")])
    path_width: FloatProperty(name="Width", default=2.0, min=1.0, max=10.0, update=_tag_redraw)
    family_only: BoolProperty(name="Family of Selected World", default=False, update=_tag_redraw,
                              description="List only the selected world's root, ancestors and children "
                                          "(refined worlds), and dim the other paths")
    # Refinement
    refine_count: IntProperty(name="Refine Worlds", default=16, min=1, soft_max=1000,
                              description="Worlds to add per refinement")
    # Queries and ranking
    boxes: CollectionProperty(type=MWB_QueryBox)
    box_index: IntProperty(name="Box", default=-1)
    rank_metric: EnumProperty(name="Rank By", items=RANK_METRICS, default="time_to_rest_s", update=_tag_redraw)
    rank_combine: EnumProperty(name="Combine", default="SUM", update=_tag_redraw,
                               items=[("SUM", "Sum", "Add the metric over the bodies"),
                                      ("MAX", "Max", "The largest value among the bodies")])
    rank_descending: BoolProperty(name="Descending", default=False, update=_tag_redraw,
                                  description="Largest values first")
    # Numbered: a saved choice is stored by its number, and "Goal's Objects" came last.
    rank_bodies: EnumProperty(
        name="Bodies", default="BOXES", update=_tag_redraw,
        items=[("BOXES", "Goal's Objects", "The objects the enabled boxes and pose parts test, or every "
                                           "simulated body without any", 3),
               ("SIMULATED", "Simulated", "Every body the simulation moves", 1),
               ("LISTED", "Listed", "The bodies stored with Use Selected", 2),
               ("SELECTED", "Selected", "The selected objects, or every simulated body when none is selected "
                                        "(changes with the selection)", 0)])
    rank_body_names: CollectionProperty(type=MWB_BodyName)
    # Goal search
    seek_want: IntProperty(name="Find", default=1, min=1, soft_max=100,
                           description="Worlds meeting every enabled box and pose part to find before stopping")
    seek_budget_worlds: IntProperty(name="Budget", default=2000, min=1, soft_max=100000,
                                    description="Most new worlds a seek makes")
    seek_budget_s: FloatProperty(name="Time Limit", default=0.0, min=0.0, unit="TIME_ABSOLUTE",
                                 description="Most seconds a seek runs; 0: no limit")
    # Preview: what to put back when it ends (saved, so a reload mid-preview can still restore).
    previewing: BoolProperty(default=False)
    preview_rigidbody_enabled: BoolProperty(default=True)
    preview_saved: CollectionProperty(type=MWB_SavedTransform)


classes = (MWB_ObjectVariation, MWB_WorldItem, MWB_SavedTransform, MWB_BodyName, MWB_QueryBox, MWB_LibraryItem,
           MWB_SceneSettings)


def register_properties():
    bpy.types.Object.mwb_variation = PointerProperty(type=MWB_ObjectVariation)
    bpy.types.Scene.mwb = PointerProperty(type=MWB_SceneSettings)


def unregister_properties():
    del bpy.types.Scene.mwb
    del bpy.types.Object.mwb_variation


RANGE_NAMES = tuple(f"{quantity}_{end}" for quantity in ("location", "rotation", "linear_velocity",
                                                         "angular_velocity") for end in ("min", "max"))


def upgrade_saved_variation(ob):
    """Store an object's ranges saved as whole numbers as floats; True if any was.

    A script that writes ob["mwb_variation"] = {"angular_velocity_max": [1, 1, 1], ...} stores an
    integer array, which the float properties read as zero: the range the file holds would be lost.
    The floats are written through the property too: from Blender 5.0 on, ob["..."] holds only the
    user's custom properties, and a file from an older Blender is opened with a copy of them in the
    add-on's own storage, integers and all. The raw value becomes floats as well, so an edit made
    in the panel afterwards is never overwritten by the file's old range.
    """
    raw = ob.get("mwb_variation")
    if raw is None or not hasattr(raw, "keys"):
        return False
    changed = False
    for name in RANGE_NAMES:
        value = raw.get(name)
        if getattr(value, "typecode", None) == "i":
            floats = [float(x) for x in value]
            raw[name] = floats
            setattr(ob.mwb_variation, name, floats)
            changed = True
    return changed


def resolved_library_path(scene):
    """Absolute library path: the property, else <blend name>.mwb next to the saved .blend, else ''."""
    from .core.paths import default_library_name
    path = scene.mwb.library_path or ("//" + default_library_name(bpy.data.filepath) if bpy.data.filepath else "")
    return bpy.path.abspath(path) if path else ""


