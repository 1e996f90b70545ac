"""Sample Worlds: export the scene, run mwb-engine as a child process, stream worlds in as they land.

The engine writes each world to the library as it finishes; the run poller (run_poller) streams
them into the view. A cancelled run's range is remembered on its library, and Sample offers to
finish it. Sampling again appends the next range of worlds.
"""
import os

import bpy

from .. import export, preview, props, sample_setup
from ..core import libraries, paths
from ..core.run import RunKind
from ..core.session import SESSION
from . import browsing
from .run_poller import FollowsRun, start_run


def next_world_index(view):
    """First world index after every world (stored or rejected) the library already holds."""
    return 0 if view is None else int(view.library.next_world_index)


def find_library_item(settings, library):
    """The scene's entry for the library file `library` (absolute path), or None."""
    return next((item for item in settings.libraries if bpy.path.abspath(item.path) == library), None)


def library_item(settings, library):
    """The scene's entry for the library file `library` (absolute path), added if missing."""
    item = find_library_item(settings, library)
    if item is None:
        item = settings.libraries.add()
        item.path = bpy.path.relpath(library) if bpy.data.filepath else library
    return item


def interrupted_run(scene):
    """(first, end) of the scene library's run cancelled before its end, or None."""
    item = find_library_item(scene.mwb, props.resolved_library_path(scene))
    return (item.interrupted_first, item.interrupted_end) if item is not None and item.interrupted_first >= 0 else None


def _varies(ob):
    v = ob.mwb_variation
    return any(any(low) or any(high) for low, high in (
        (v.location_min, v.location_max), (v.rotation_min, v.rotation_max),
        (v.linear_velocity_min, v.linear_velocity_max), (v.angular_velocity_min, v.angular_velocity_max)))


def sample_blocker(scene):
    """Why Sample cannot start now, in the words the panel and the button's tooltip show, or ''."""
    if SESSION.run is not None:
        return f"{SESSION.run.label} is running; wait for it or cancel it first"
    rbw = scene.rigidbody_world
    if rbw is None or rbw.collection is None:
        return "Add a Rigid Body World first (Scene Properties > Rigid Body World)"
    simulated = export.simulated_object_names(scene)
    if not simulated:
        return "Nothing to simulate: make an object an Active rigid body (Object > Rigid Body > Add Active)"
    if not props.resolved_library_path(scene):
        return "Save the .blend first (the library is written next to it) or set a library path"
    if scene.mwb.alpha == 0 and not any(_varies(scene.objects[name]) for name in simulated if name in scene.objects):
        return ("Every world would be the same: give an object a variation range (Physics > Many Worlds "
                "Variation) or raise Perturbation (Expert Settings)")
    return ""


def start_sampling(context, finish_interrupted=True):
    """Export, validate and start the engine. Returns (ok, message, export problems).

    With a cancelled run on record for the library and `finish_interrupted`, the run's range is
    sampled again (the engine skips the worlds it already stored); otherwise the next worlds are
    added. When the scene or the run settings changed since the library was sampled, the run goes
    into a library of its own beside it (or an earlier one of the same run) and the old one stays.
    """
    scene = context.scene
    settings = scene.mwb
    blocker = sample_blocker(scene)
    if blocker:
        return False, blocker, []
    library = props.resolved_library_path(scene)
    # Export the user's scene, not the preview's poses.
    preview.end(scene)
    if os.path.isfile(library) and (SESSION.view is None or SESSION.view.path != library):
        libraries.open_library(library, scene)
    if SESSION.view is not None:
        SESSION.view.poll()
    interrupted = interrupted_run(scene) if finish_interrupted else None
    first, count = (interrupted[0], interrupted[1] - interrupted[0]) if interrupted else \
        (next_world_index(SESSION.view), settings.world_count)
    known = [bpy.path.abspath(item.path) for item in settings.libraries]
    try:
        paths.engine_command()  # no engine: say so before exporting
        request, chosen, first, warnings = sample_setup.sample_into_matching_library(context, library, known, first, count)
    except sample_setup.RunSetupError as error:
        SESSION.export_warnings = list(error.problems)
        return False, str(error), error.problems
    except FileNotFoundError as error:
        return False, str(error), []
    note = ""
    if chosen != library:
        note = (f" into {os.path.basename(chosen)}: the scene or settings changed since "
                f"{os.path.basename(library)} was sampled (it is kept)")
        settings.library_path = bpy.path.relpath(chosen) if bpy.data.filepath else chosen
        library_item(settings, library)
        libraries.open_library(chosen, scene)
        browsing.sync_world_list(scene)
    SESSION.export_warnings = list(warnings)
    item = library_item(settings, chosen)
    settings["library_index"] = list(settings.libraries).index(item)
    end = first + count
    start_run(scene, RunKind.SAMPLE, request, chosen, f"Sampling worlds {first} to {end - 1}{note}", note=note,
              follower=SampleFollower(), world_range=(first, end))
    return True, SESSION.status, warnings


class SampleFollower:
    """A sampling run's lines; at its end, its range is remembered on its library if it was
    cancelled (Sample then offers to finish it) and forgotten once the run reached its end."""

    def follow(self, scene, run):
        return run.running_text(SESSION.status)

    def ended(self, scene, run, stored):
        item = library_item(scene.mwb, run.library)
        if run.cancel_requested:
            item.interrupted_first, item.interrupted_end = run.world_range
            return run.cancelled_text(stored)
        item.interrupted_first = item.interrupted_end = -1
        return run.finished_text(stored)


class MWB_OT_sample(FollowsRun, bpy.types.Operator):
    """Sample plausible worlds of the rigid body scene into the library (runs the engine in the background)"""
    bl_idname = "mwb.sample"
    bl_label = "Sample Worlds"

    mode: bpy.props.EnumProperty(
        name="Mode", default="ASK", options={"SKIP_SAVE"},
        items=[("ASK", "Ask", "Offer to finish a cancelled run when there is one (from a script: finish it)"),
               ("FINISH", "Finish", "Sample the worlds a cancelled run did not reach"),
               ("NEW", "New Worlds", "Add the next worlds, leaving a cancelled run as it is")])

    @classmethod
    def poll(cls, context):
        blocker = sample_blocker(context.scene)
        if blocker:
            cls.poll_message_set(blocker)
        return not blocker

    def invoke(self, context, event):
        interrupted = interrupted_run(context.scene)
        if self.mode != "ASK" or interrupted is None:
            return super().invoke(context, event)
        first, end = interrupted

        def draw(menu, _context):
            menu.layout.operator("mwb.sample", text=f"Finish Worlds {first} to {end - 1}", icon="PLAY").mode = "FINISH"
            menu.layout.operator("mwb.sample", text="Sample New Worlds", icon="ADD").mode = "NEW"

        context.window_manager.popup_menu(draw, title="The last run was cancelled", icon="QUESTION")
        return {"CANCELLED"}

    def _start(self, context):
        ok, message, problems = start_sampling(context, finish_interrupted=self.mode != "NEW")
        for line in problems:
            self.report({"WARNING"}, line)
        self.report({"INFO"} if ok else {"ERROR"}, message)
        return ok


class MWB_OT_check_scene(bpy.types.Operator):
    """List what the engine cannot run exactly as Blender would"""
    bl_idname = "mwb.check_scene"
    bl_label = "Check Scene"

    def execute(self, context):
        result, invalid = export.export_and_validate(context)
        SESSION.export_warnings = list(result.problems + invalid)
        for line in SESSION.export_warnings:
            self.report({"WARNING"}, line)
        if not result.problems and not invalid:
            self.report({"INFO"}, f"{len(result.scene['bodies'])} bodies, "
                                  f"{len(result.scene['constraints'])} constraints: everything is supported")
        return {"FINISHED"}


classes = (MWB_OT_sample, MWB_OT_check_scene)
