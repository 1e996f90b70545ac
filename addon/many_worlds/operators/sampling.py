"""Sample Worlds: export the scene, run mwb-engine as a child process, stream worlds in as they land.

The engine writes each world to the library as it finishes; a `bpy.app.timers` poller reads its
progress events and polls the library, so paths appear in the viewport while the UI stays live.
Cancel (button or Esc) asks the engine to stop: it finishes the record it is writing and exits,
and every finished world stays in the file. Sampling again appends the next range of worlds.
"""
import os
import sys

import bpy

from .. import export, preview, props, scene_boxes, runs
from ..core import engine as engine_process
from ..core import paths
from ..core.session import SESSION
from . import browsing

POLL_INTERVAL_S = 0.25
# What a finished run made, by SESSION.run_label; {done} is the count of new worlds.
FINISHED_TEXT = {"Sampling": "Sampled {done} worlds", "Refining": "Refined into {done} worlds",
                 "Adding": "Added into {done} new worlds", "Removing": "Removed from {done} new worlds",
                 "Updating": "Updated in {done} new worlds"}


def _set_status_text(text):
    # The status bar belongs to the workspace; there is none in background mode.
    workspace = getattr(bpy.context, "workspace", None)
    if workspace is not None:
        workspace.status_text_set(text)


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


def start_sampling(context, finish_interrupted=True):
    """Export, validate and start the engine. Returns (ok, message, export problems).

    With a cancelled run on record for the library and `finish_interrupted`, the run's range is
    sampled again (the engine skips the worlds it already stored); otherwise the next worlds are
    added. When the scene or the run settings changed since the library was sampled, the run goes
    into a library of its own beside it (or an earlier one of the same run) and the old one stays.
    """
    scene = context.scene
    settings = scene.mwb
    if SESSION.engine is not None:
        return False, f"{SESSION.run_label} is already running", []
    library = props.resolved_library_path(scene)
    if not library:
        return False, "Save the .blend first (the library is written next to it) or set a library path", []
    # Export the user's scene, not the preview's poses.
    preview.end(scene)
    if os.path.isfile(library) and (SESSION.view is None or SESSION.view.path != library):
        browsing.open_library(scene, library)
    if SESSION.view is not None:
        SESSION.view.poll()
    interrupted = interrupted_run(scene) if finish_interrupted else None
    first, count = (interrupted[0], interrupted[1] - interrupted[0]) if interrupted else \
        (next_world_index(SESSION.view), settings.world_count)
    known = [bpy.path.abspath(item.path) for item in settings.libraries]
    try:
        engine = paths.engine_path()
        request, chosen, first, warnings = runs.sample_into_matching_library(context, library, known, first, count)
    except runs.RunSetupError as error:
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
        browsing.open_library(scene, chosen)
        browsing.sync_world_list(scene)
    SESSION.export_warnings = list(warnings)
    item = library_item(settings, chosen)
    settings["library_index"] = list(settings.libraries).index(item)
    end = first + count
    SESSION.sampling_range = (first, end)
    start_run(scene, request, chosen, "Sampling", f"Sampling worlds {first} to {end - 1}{note}", note, engine=engine)
    return True, SESSION.status, warnings


def start_run(scene, request, library, label, status, note="", follower=None, engine=None):
    """Start the engine on `request` (core.engine) writing `library`; the poller streams its worlds
    into the view. Raises FileNotFoundError when there is no engine.

    label: what the run does ("Sampling", "Refining", "Adding", "Removing", "Updating", "Seeking"),
    for the panel and the end of run message; status: the panel's line until the first progress
    arrives; note: said again in the end of run message; follower: for a run whose progress is
    more than worlds done, an object whose `follow(scene, run)` (each poll while it runs) and
    `ended(scene, run, stored)` (once it ended, unless it failed) return the panel's line.
    """
    run = engine_process.EngineRun(request, engine)
    SESSION.run_note = note
    SESSION.run_follower = follower
    SESSION.engine = run
    SESSION.sampling_scene = scene.name
    SESSION.sampling_library = library
    SESSION.run_label = label
    SESSION.last_error = ""
    SESSION.status = status
    if not bpy.app.timers.is_registered(poll_sampling):
        bpy.app.timers.register(poll_sampling, first_interval=POLL_INTERVAL_S)


def _stream_worlds(scene):
    """Open the library once the engine has written its header, then pick up new worlds."""
    if SESSION.view is None or SESSION.view.path != SESSION.sampling_library:
        if not os.path.isfile(SESSION.sampling_library):
            return 0
        try:
            browsing.open_library(scene, SESSION.sampling_library)
        except IOError:
            return 0  # header not complete yet: try again on the next tick
        return len(SESSION.view.world_indices) if SESSION.view else 0
    added = SESSION.view.poll()
    if added:
        browsing.sync_world_list(scene)
        # New worlds arrive matching; the boxes decide (the index adds only the new paths).
        scene_boxes.refresh(scene)
    return added


def poll_sampling():
    """Timer body: progress, streaming, and the end of the run. Returns the next interval or None."""
    run = SESSION.engine
    if run is None:
        return None
    scene = bpy.data.scenes.get(SESSION.sampling_scene)
    finished = run.finished()
    if scene is not None and _stream_worlds(scene):
        browsing.tag_redraw_all()
    done, total, _ = run.progress()
    follower = SESSION.run_follower
    if not finished:
        SESSION.status = (follower.follow(scene, run) if follower is not None and scene is not None
                          else f"{SESSION.run_label}: {done} / {total} worlds")
        _set_status_text(f"Many Worlds: {SESSION.status} (Esc to cancel)")
        return POLL_INTERVAL_S
    failed = run.failure()
    stored = len(SESSION.view.world_indices) if SESSION.view else 0
    if failed:
        failure = failed.message
        if failed.code == engine_process.OTHER_RUN:
            failure += (" - the scene or settings changed since this library was sampled; set another "
                        "library path (or remove the file) to start a new library")
        SESSION.last_error = failure
        SESSION.status = f"{SESSION.run_label} failed: {failure}"
        print(f"Many Worlds: {SESSION.status}", file=sys.stderr)
    elif follower is not None and scene is not None:
        SESSION.status = follower.ended(scene, run, stored)
    elif run.cancel_requested:
        SESSION.status = f"{SESSION.run_label} cancelled; the library keeps {stored} worlds"
        _remember_interruption(scene, True)
    else:
        _remember_interruption(scene, False)
        made = FINISHED_TEXT.get(SESSION.run_label, "{done} new worlds").format(done=done)
        SESSION.status = f"{made}{SESSION.run_note}; the library holds {stored}"
    SESSION.engine = None
    SESSION.run_follower = None
    _set_status_text(None)
    browsing.tag_redraw_all()
    return None


def _remember_interruption(scene, cancelled):
    """After a sampling run: note its range on its library when it was cancelled (Sample then
    offers to finish it), forget it when the run reached its end."""
    if scene is None or SESSION.run_label != "Sampling" or SESSION.sampling_range is None:
        return
    item = library_item(scene.mwb, SESSION.sampling_library)
    if cancelled:
        item.interrupted_first, item.interrupted_end = SESSION.sampling_range
    else:
        item.interrupted_first = item.interrupted_end = -1
    SESSION.sampling_range = None


def cancel_sampling():
    if SESSION.engine is not None:
        SESSION.engine.cancel()


def stop_for_unregister():
    """Stop the engine and the poller (add-on disabled or Blender quitting); finished worlds stay."""
    if bpy.app.timers.is_registered(poll_sampling):
        bpy.app.timers.unregister(poll_sampling)
    if SESSION.engine is not None:
        SESSION.engine.cancel()
        try:
            SESSION.engine.wait(30)
        except Exception:
            SESSION.engine.kill()
        SESSION.engine = None


class FollowsEngineRun:
    """The operator side of a button that starts an engine run. A subclass implements
    `_start(context)` (True when the run started; it reports why not). execute only starts the
    run; invoke (a button press) also stays modal to let Esc cancel and to report the end, while
    the timer poller does the work."""

    _timer = None

    def execute(self, context):
        return {"FINISHED"} if self._start(context) else {"CANCELLED"}

    def invoke(self, context, event):
        if not self._start(context):
            return {"CANCELLED"}
        self._timer = context.window_manager.event_timer_add(POLL_INTERVAL_S, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            cancel_sampling()
        if SESSION.engine is not None:
            return {"PASS_THROUGH"}
        context.window_manager.event_timer_remove(self._timer)
        if SESSION.last_error:
            self.report({"ERROR"}, SESSION.last_error)
        else:
            self.report({"INFO"}, SESSION.status)
        return {"FINISHED"}


class MWB_OT_sample(FollowsEngineRun, bpy.types.Operator):
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
        return SESSION.engine is None and context.scene.rigidbody_world is not None

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


class MWB_OT_cancel_sampling(bpy.types.Operator):
    """Stop sampling, refining, adding, removing or seeking; every finished world stays in the library"""
    bl_idname = "mwb.cancel_sampling"
    bl_label = "Cancel Sampling"

    @classmethod
    def poll(cls, context):
        return SESSION.engine is not None

    def execute(self, context):
        cancel_sampling()
        return {"FINISHED"}


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


classes = (MWB_OT_sample, MWB_OT_cancel_sampling, MWB_OT_check_scene)
