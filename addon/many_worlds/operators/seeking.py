"""Seek: refine the open library's worlds until some meet every enabled part of the goal.

The goal is the enabled boxes and pose parts, each met after the part it is ordered after (if that
one is enabled too). `mwb-engine seek` refines worlds again and again, appending each to the library as
it is made; the run goes through the run poller, so worlds stream into the list and the
viewport, Esc / Cancel stops it and keeps every world made, and only one engine run exists at a
time. Whenever the engine names a new best world, it is selected and previewed as if clicked in
the Worlds list.
"""
import os

import bpy

from .. import scene_boxes
from ..core import engine as engine_process
from ..core import goal as core_goal
from ..core import paths
from ..core.session import SESSION
from ..core.run import RunKind
from .run_poller import FollowsRun, start_run


def seek_problem(scene):
    """Why a seek cannot start now (one line), or ''."""
    if SESSION.run is not None:
        return f"{SESSION.run.label} is running; wait for it or cancel it first"
    if SESSION.view is None:
        return "Open or sample a library first"
    if not scene_boxes.enabled_specs(scene, SESSION.view):
        return "Draw a box or add a pose first: the goal is every enabled part (over bodies the library has)"
    return SESSION.goal_problem


class SeekFollower:
    """The panel's line while a seek runs and when it ends; selects each new best world."""

    def __init__(self):
        self.selected = -1
        self.shown = None   # the SeekProgress the panel shows

    def _select(self, scene, world):
        """Select and preview `world` once it is in the view (the Worlds list's own path)."""
        view = SESSION.view
        if world < 0 or world == self.selected or view is None or world not in view.world_indices:
            return
        scene.mwb.world_list_index = view.world_indices.index(world)
        self.selected = world

    def follow(self, scene, run):
        progress = run.seek_progress()
        view = SESSION.view
        # The panel names a best world only once it has streamed in and can be selected.
        if progress is not None and (progress.best_world < 0 or (
                view is not None and progress.best_world in view.world_indices)):
            self.shown = progress
            self._select(scene, progress.best_world)
        if self.shown is None:
            return "Seeking: first worlds under way"
        return f"Seeking: {self.shown.text}"

    def ended(self, scene, run, stored):
        outcome = engine_process.SeekOutcome.from_summary(run.summary())
        progress = run.seek_progress()
        if outcome is not None:
            self._select(scene, outcome.best)
        elif progress is not None:
            self._select(scene, progress.best_world)
        if run.cancel_requested:
            where = f"{progress.text}; " if progress is not None else ""
            return f"Seek cancelled: {where}the library keeps {stored:,} worlds"
        if outcome is None:
            return f"Seek ended without a summary; the library holds {stored:,} worlds"
        return outcome.text


def start_seek(context):
    """Write the goal of the enabled boxes and pose parts beside the open library and start the
    engine seeking. Returns (ok, message)."""
    scene = context.scene
    settings = scene.mwb
    problem = seek_problem(scene)
    if problem:
        return False, problem
    view = SESSION.view
    specs = scene_boxes.enabled_specs(scene, view)
    noun = "world" if settings.seek_want == 1 else "worlds"
    parts = "1 part" if len(specs) == 1 else f"{len(specs)} parts"
    try:
        goal_path = core_goal.write_goal(paths.goal_json_path(view.path), specs)
        request = engine_process.SeekRequest(view.path, goal_path, settings.seek_want, settings.seek_budget_worlds,
                                             settings.seek_budget_s, threads=settings.threads)
        start_run(scene, RunKind.SEEK, request, view.path,
                  f"Seeking {settings.seek_want} {noun} meeting {parts} in {os.path.basename(view.path)}",
                  follower=SeekFollower())
    except (ValueError, OSError) as error:
        return False, str(error)
    return True, SESSION.status


class MWB_OT_seek(FollowsRun, bpy.types.Operator):
    """Refine worlds until some meet every enabled box and pose (in their order); new worlds stream
    in and the best one is previewed (Esc cancels; every world made stays)"""
    bl_idname = "mwb.seek"
    bl_label = "Seek"

    @classmethod
    def poll(cls, context):
        problem = seek_problem(context.scene)
        if problem:
            cls.poll_message_set(problem)
        return not problem

    def _start(self, context):
        ok, message = start_seek(context)
        self.report({"INFO"} if ok else {"ERROR"}, message)
        return ok


classes = (MWB_OT_seek,)
