"""Refine: drag a box over the part of the selected objects' paths to change, in the selected world.

The first time any selected object's path enters the box's frustum (t_min, from the path index)
is where the new worlds branch: `mwb-engine refine` re-creates the world up to t_min and
simulates the selected objects anew, appending children of the world to the same library. The
run goes through the run poller, so children stream into the list and the viewport as they
land, Esc / Cancel keeps the finished ones, and only one engine run exists at a time.
"""
import bpy
from bpy.props import FloatVectorProperty, IntProperty, IntVectorProperty

from .. import scene_boxes
from ..core import engine as engine_process
from ..core.library_query import normalized_rect, too_small_text
from ..core.session import SESSION
from ..draw import boxes as box_overlay
from ..core.run import RunKind
from . import run_poller
from .boxes import BoxDrag, camera_of


def selected_body_names(context, view, world):
    """The selected objects the simulation moves in `world`, as library body names."""
    simulated = {view.body_names[i] for i in view.present_bodies(world, view.simulated_bodies())}
    return [ob.name for ob in (getattr(context, "selected_objects", None) or []) if ob.name in simulated]


def refine_problem(context, world):
    """Why refining cannot start now (one line), or '' when it can."""
    view = SESSION.view
    if SESSION.run is not None:
        return f"{SESSION.run.label} is running; wait for it or cancel it first"
    if view is None:
        return "Open or sample a library first"
    if world not in view.world_indices:
        return "Select a world to refine"
    if not selected_body_names(context, view, world):
        return f"Select the objects to refine (bodies the simulation moves in world {world})"
    return ""


def first_time_inside(view, world, body_names, view_matrix, projection_matrix, size, rect):
    """Seconds at which any of the bodies' paths in `world` first enters the box; -1 if never."""
    spec = scene_boxes.drag_spec(view, view_matrix, projection_matrix, size, rect, False, body_names)
    lq = scene_boxes.library_query()
    if spec is None or lq is None:
        return -1.0
    lq.complete()
    return float(lq.index.first_time_inside(int(world), list(spec.bodies), lq.native_box(spec)))


def start_refining(scene, world, body_names, time_s):
    """Start the engine child refining `world` at `time_s`; its children stream in through the poller."""
    settings = scene.mwb
    view = SESSION.view
    request = engine_process.RefineRequest(
        view.path, world, tuple(view.present_bodies(world, scene_boxes.body_indices(body_names, view))), time_s,
        settings.refine_count, settings.threads)
    run_poller.start_run(scene, RunKind.REFINE, request, view.path,
                         f"Refining {', '.join(body_names)} in world {world} from {time_s:.2f} s "
                         f"into {settings.refine_count} worlds")


def refine_through_box(operator, context, view_matrix, projection_matrix, size, rect):
    """Find t_min for the box and start refining; reports to `operator`. Returns True if started."""
    world = context.scene.mwb.selected_world
    problem = refine_problem(context, world)
    if problem:
        operator.report({"ERROR"}, problem)
        return False
    names = selected_body_names(context, SESSION.view, world)
    t_min = first_time_inside(SESSION.view, world, names, view_matrix, projection_matrix, size, rect)
    if t_min < 0:
        # Not an error of the tool: the user learns the box misses, and nothing runs.
        SESSION.status = f"the selected objects never enter that box in world {world}"
        operator.report({"WARNING"}, SESSION.status)
        return False
    try:
        start_refining(context.scene, world, names, t_min)
    except (FileNotFoundError, OSError) as error:
        operator.report({"ERROR"}, str(error))
        return False
    operator.report({"INFO"}, SESSION.status)
    return True


class MWB_OT_refine(bpy.types.Operator):
    """Refine the selected objects in the selected world from where they first enter a box given by
    numbers (scripts, tests); the box tool is Refine Selected"""
    bl_idname = "mwb.refine"
    bl_label = "Refine Through Box"

    rect: FloatVectorProperty(name="Rectangle", size=4, description="x0, y0, x1, y1, region pixels")
    view_matrix: FloatVectorProperty(name="View Matrix", size=16,
                                     description="World to camera, row-major; all zero: the current 3D view's")
    projection_matrix: FloatVectorProperty(name="Projection Matrix", size=16,
                                           description="Camera to clip, row-major; all zero: the current 3D view's")
    region_size: IntVectorProperty(name="Region Size", size=2, description="Width, height; 0: the current region's")

    @classmethod
    def poll(cls, context):
        return SESSION.run is None and SESSION.view is not None

    def execute(self, context):
        camera = camera_of(self, context)
        if camera is None:
            return {"CANCELLED"}
        view, projection, size = camera
        problem = too_small_text(self.rect)
        if problem:
            self.report({"ERROR"}, problem)
            return {"CANCELLED"}
        rect = normalized_rect(*self.rect)
        started = refine_through_box(self, context, [view[i:i + 4] for i in range(0, 16, 4)],
                                     [projection[i:i + 4] for i in range(0, 16, 4)], size, rect)
        return {"FINISHED"} if started else {"CANCELLED"}


class MWB_OT_refine_box(BoxDrag, bpy.types.Operator):
    """Drag a box over the part of the selected objects' path to change in the selected world: new
    worlds re-simulate them from where they first enter it (Esc cancels; finished worlds stay)"""
    bl_idname = "mwb.refine_box"
    bl_label = "Refine Selected"

    refine_count: IntProperty(name="Worlds", default=0, min=0,
                              description="Worlds to add; 0: the scene's Refine Worlds setting")

    _hint = "Many Worlds: drag a box over the part of the path to refine (Esc / right-click: cancel)"

    @classmethod
    def poll(cls, context):
        return context.window is not None and SESSION.run is None and SESSION.view is not None

    def _prepare(self, context):
        self._waiting = False
        self._timer = None
        self._world = context.scene.mwb.selected_world
        problem = refine_problem(context, self._world)
        if problem:
            self.report({"ERROR"}, problem)
            return False
        if self.refine_count > 0:
            context.scene.mwb.refine_count = self.refine_count
        self._bodies = selected_body_names(context, SESSION.view, self._world)
        return True

    def _dragged(self, context, event):
        region = self._region
        box_overlay.OVERLAY.dragging = (region.as_pointer(), self._rect(), False)
        # The branch time follows the box while it is dragged: one world, one lookup per move.
        t_min = first_time_inside(SESSION.view, self._world, self._bodies, region.data.view_matrix,
                                  region.data.window_matrix, (region.width, region.height), self._rect())
        where = f"from {t_min:.2f} s" if t_min >= 0 else "never enters the box"
        return (f"Refine {', '.join(self._bodies)} in world {self._world}: {where} | "
                "Esc / right-click: cancel")

    def _released(self, context, event, rect):
        region = self._region
        if not refine_through_box(self, context, region.data.view_matrix, region.data.window_matrix,
                                  (region.width, region.height), rect):
            return {"CANCELLED"}
        # Stay modal only to catch Esc and report the end; the timer poller streams the worlds.
        self._waiting = True
        self._timer = context.window_manager.event_timer_add(run_poller.POLL_INTERVAL_S, window=context.window)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if not self._waiting:
            return super().modal(context, event)
        if event.type == "ESC" and event.value == "PRESS":
            run_poller.cancel_run()
        if SESSION.run is not None:
            return {"PASS_THROUGH"}
        context.window_manager.event_timer_remove(self._timer)
        self.report({"ERROR"} if SESSION.last_error else {"INFO"}, SESSION.last_error or SESSION.status)
        return {"FINISHED"}


classes = (MWB_OT_refine, MWB_OT_refine_box)
