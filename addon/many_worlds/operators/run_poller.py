"""Every engine run of the add-on goes through here: start it, stream its worlds into the open
view while it runs, turn its progress into the panel's line, and read how it ended.

A `bpy.app.timers` poller reads the run's events (core.run.Run) and polls the library, so paths
appear in the viewport while the UI stays live. Cancel (button or Esc) asks the engine to stop: it
finishes the record it is writing and exits, and every finished world stays in the file.
"""
import os
import sys

import bpy

from .. import scene_boxes
from ..core import engine as engine_process
from ..core import libraries
from ..core.run import Run
from ..core.session import SESSION
from . import browsing

POLL_INTERVAL_S = 0.25


def _set_status_text(text):
    # The status bar belongs to the workspace; there is none in background mode.
    workspace = getattr(bpy.context, "workspace", None)
    if workspace is not None:
        workspace.status_text_set(text)


def start_run(scene, kind, request, library, status, note="", follower=None, world_range=None, engine=None):
    """Start the engine on `request` (core.engine) writing `library`, as a Run of `kind`; the
    poller streams its worlds into the view. status: the panel's line until the first progress
    arrives. Returns the Run; raises FileNotFoundError when there is no engine."""
    run = Run(kind, request, scene.name, library, note=note, world_range=world_range, follower=follower,
              engine=engine)
    SESSION.runs.append(run)
    SESSION.last_error = ""
    SESSION.run_warnings = []
    SESSION.status = status
    if not bpy.app.timers.is_registered(poll_run):
        bpy.app.timers.register(poll_run, first_interval=POLL_INTERVAL_S)
    return run


def _stream_worlds(scene, run):
    """Open the library once the engine has written its header, then pick up new worlds."""
    if SESSION.view is None or SESSION.view.path != run.library:
        if not os.path.isfile(run.library):
            return 0
        try:
            libraries.open_library(run.library, scene)
        except IOError:
            return 0  # header not complete yet: try again on the next tick
        return len(SESSION.view.world_indices) if SESSION.view else 0
    added = SESSION.view.poll()
    if added:
        browsing.sync_world_list(scene)
        # New worlds arrive matching; the boxes decide (the index adds only the new paths).
        scene_boxes.refresh(scene)
    return added


def _ended_text(scene, run, stored):
    failed = run.failure()
    if failed:
        failure = failed.message
        if failed.code == engine_process.OTHER_RUN:
            failure += (" - the scene or settings changed since this library was sampled; set another "
                        "library path (or remove the file) to start a new library")
        SESSION.last_error = failure
        return f"{run.label} failed: {failure}"
    if run.follower is not None and scene is not None:
        return run.follower.ended(scene, run, stored)
    return run.cancelled_text(stored) if run.cancel_requested else run.finished_text(stored)


def poll_run():
    """Timer body: progress, streaming, and the end of the run. Returns the next interval or None."""
    run = SESSION.run
    if run is None:
        return None
    scene = bpy.data.scenes.get(run.scene_name)
    finished = run.finished()
    if scene is not None and _stream_worlds(scene, run):
        browsing.tag_redraw_all()
    if not finished:
        SESSION.status = (run.follower.follow(scene, run) if run.follower is not None and scene is not None
                          else run.running_text(SESSION.status))
        _set_status_text(f"Many Worlds: {SESSION.status} (Esc to cancel)")
        return POLL_INTERVAL_S
    stored = len(SESSION.view.world_indices) if SESSION.view else 0
    SESSION.status = _ended_text(scene, run, stored)
    SESSION.run_warnings = run.warnings()
    for line in SESSION.run_warnings:
        print(f"Many Worlds: warning: {line}", file=sys.stderr)
    if SESSION.last_error:
        print(f"Many Worlds: {SESSION.status}", file=sys.stderr)
    run.ended = True
    _set_status_text(None)
    browsing.tag_redraw_all()
    return None


def cancel_run():
    if SESSION.run is not None:
        SESSION.run.cancel()


def stop_for_unregister():
    """Stop the engine and the poller (add-on disabled or Blender quitting); finished worlds stay."""
    if bpy.app.timers.is_registered(poll_run):
        bpy.app.timers.unregister(poll_run)
    run = SESSION.run
    if run is not None:
        run.cancel()
        try:
            run.wait(30)
        except Exception:
            run.kill()
        run.ended = True


class FollowsRun:
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
            cancel_run()
        if SESSION.run is not None:
            return {"PASS_THROUGH"}
        context.window_manager.event_timer_remove(self._timer)
        for line in SESSION.run_warnings:
            self.report({"WARNING"}, line)
        if SESSION.last_error:
            self.report({"ERROR"}, SESSION.last_error)
        else:
            self.report({"INFO"}, SESSION.status)
        return {"FINISHED"}


class MWB_OT_cancel_sampling(bpy.types.Operator):
    """Stop sampling, refining, adding, removing or seeking; every finished world stays in the library"""
    bl_idname = "mwb.cancel_sampling"
    bl_label = "Cancel Sampling"

    @classmethod
    def poll(cls, context):
        return SESSION.run is not None

    def execute(self, context):
        cancel_run()
        return {"FINISHED"}


classes = (MWB_OT_cancel_sampling,)
