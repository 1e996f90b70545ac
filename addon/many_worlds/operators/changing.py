"""Add Selected to Worlds / Remove from Worlds / Update Selected in Worlds: change which objects
exist in the selected world, or how they start.

After sampling, the user places a new object (or deletes one, or picks one, or moves one) and asks
for worlds with it (or without it, or with it where it is now): `mwb-engine refine --add /
--remove / --update` appends children of the selected world in which the objects exist from 0 s
(or not at all, or as a new body for their new definition); whatever they touch (or touched) is
simulated anew, and every other body replays the world bit for bit. The run goes through the
run poller like a refinement: children stream into the list and the viewport as they land,
Esc / Cancel keeps the finished ones, and only one engine run exists at a time.
"""
import bpy

from .. import export, preview
from ..core import engine as engine_process
from ..core import paths
from ..core.session import SESSION
from ..core.run import RunKind
from .run_poller import FollowsRun, start_run


def _world_problem(scene):
    """Why no world can be changed now (one line), or ''."""
    view = SESSION.view
    if SESSION.run is not None:
        return f"{SESSION.run.label} is running; wait for it or cancel it first"
    if view is None:
        return "Open or sample a library first"
    if scene.mwb.selected_world not in view.world_indices:
        return "Select a world first"
    return ""


def _in_world(view, world):
    """Names of the library bodies that exist in `world`."""
    present = view.present(world)
    return [name for i, name in enumerate(view.body_names) if present[i]]


def _selected(context):
    return sorted(getattr(context, "selected_objects", None) or [], key=lambda ob: ob.name)


def _selected_bodies(context, in_world_wanted, nothing_selected):
    """(names, problem): the selected objects, each with a rigid body and in the selected world (or
    not, as `in_world_wanted` says), or why they cannot be taken."""
    problem = _world_problem(context.scene)
    if problem:
        return [], problem
    world = context.scene.mwb.selected_world
    selected = _selected(context)
    if not selected:
        return [], nothing_selected
    in_world = set(_in_world(SESSION.view, world))
    for ob in selected:
        if ob.rigid_body is None:
            return [], f"{ob.name} has no rigid body (Physics > Rigid Body)"
        if in_world_wanted and ob.name not in in_world:
            return [], f"{ob.name} is not in world {world}; add it instead"
        if not in_world_wanted and ob.name in in_world:
            return [], f"{ob.name} is already in world {world}"
    return [ob.name for ob in selected], ""


def bodies_to_add(context):
    """(names, problem): the selected objects to add to the selected world, or why they cannot be."""
    return _selected_bodies(context, False,
                            "Select the objects to add (objects with a rigid body that are not in the world)")


def bodies_to_remove(context):
    """(names, deleted, problem): the bodies to remove from the selected world (the selected objects
    in it, then bodies in it whose objects are gone from the scene), those of them that are gone,
    or why there are none."""
    problem = _world_problem(context.scene)
    if problem:
        return [], [], problem
    world = context.scene.mwb.selected_world
    selected = {ob.name for ob in _selected(context)}
    in_world = _in_world(SESSION.view, world)
    deleted = [name for name in in_world if name not in context.scene.objects]
    names = [name for name in in_world if name in selected] + deleted
    if not names:
        if selected:
            return [], [], f"None of the selected objects is in world {world}"
        return [], [], f"Select the objects to remove from world {world} (or delete them from the scene)"
    return names, deleted, ""


def bodies_to_update(context):
    """(names, problem): the selected objects the selected world has, to start them as they are
    now (moved, new settings), or why they cannot be."""
    return _selected_bodies(context, True,
                            "Select the objects to update (objects in the world, changed since it was made)")


def _start(scene, world, add_names, remove_names, scene_json, kind, status, update_names=()):
    """Build the engine command and start the run; returns '' or why it could not start."""
    settings = scene.mwb
    view = SESSION.view
    try:
        request = engine_process.ChangeRequest(view.path, world, add=add_names, remove=remove_names,
                                               update=update_names, scene_json=scene_json,
                                               count=settings.refine_count, threads=settings.threads)
        start_run(scene, kind, request, view.path, status)
    except (ValueError, OSError) as error:
        return str(error)
    return ""


def start_adding(context):
    """Export the scene and start adding the selected objects. Returns (ok, message, warnings)."""
    names, problem = bodies_to_add(context)
    if problem:
        return False, problem, []
    return _export_and_start(context, names, updating=False)


def start_updating(context):
    """Export the scene and start updating the selected objects. Returns (ok, message, warnings)."""
    names, problem = bodies_to_update(context)
    if problem:
        return False, problem, []
    return _export_and_start(context, names, updating=True)


def _export_and_start(context, names, updating):
    """Export the scene as it is now and start the run that adds (or updates) `names` in the
    selected world. Returns (ok, message, warnings)."""
    scene = context.scene
    # Export the user's scene, not the preview's poses.
    preview.end(scene)
    result, invalid = export.export_and_validate(context)
    if result.scene is None or invalid:
        return False, "The scene cannot be exported: " + "; ".join(invalid or result.problems), []
    warnings = [line for line in result.problems if line.split(":")[0] in names]
    exported = {body["name"] for body in result.scene["bodies"]}
    outside = [name for name in names if name not in exported]
    if outside:
        return False, f"{outside[0]} is not in the scene's Rigid Body World collection", warnings
    # Next to the library, apart from the sampled scene's file, which stays as it was sampled.
    scene_json = paths.added_scene_json_path(SESSION.view.path)
    try:
        with open(scene_json, "w") as f:
            f.write(result.to_json())
    except OSError as error:
        return False, f"Cannot write {scene_json}: {error.strerror}", warnings
    world, count = scene.mwb.selected_world, scene.mwb.refine_count
    if updating:
        problem = _start(scene, world, [], [], scene_json, RunKind.UPDATE,
                         f"Updating {', '.join(names)} in world {world} in {count} new worlds", update_names=names)
    else:
        problem = _start(scene, world, names, [], scene_json, RunKind.ADD,
                         f"Adding {', '.join(names)} to world {world} in {count} new worlds")
    return not problem, problem or SESSION.status, warnings


def start_removing(context):
    """Start removing the chosen bodies from the selected world. Returns (ok, message, warnings)."""
    names, deleted, problem = bodies_to_remove(context)
    if problem:
        return False, problem, []
    scene = context.scene
    world, count = scene.mwb.selected_world, scene.mwb.refine_count
    shown = [f"{name} (deleted from the scene)" if name in deleted else name for name in names]
    problem = _start(scene, world, [], names, "", RunKind.REMOVE,
                     f"Removing {', '.join(shown)} from world {world} in {count} new worlds")
    return not problem, problem or SESSION.status, []


class ChangesWorldObjects(FollowsRun):
    """A button that starts an engine run changing the selected world's objects: `starter(context)`
    returns (started, message, warnings)."""

    starter = None

    @classmethod
    def poll(cls, context):
        return SESSION.run is None

    def _start(self, context):
        ok, message, warnings = type(self).starter(context)
        for line in warnings:
            self.report({"WARNING"}, line)
        self.report({"INFO"} if ok else {"ERROR"}, message)
        return ok


class MWB_OT_add_to_worlds(ChangesWorldObjects, bpy.types.Operator):
    """New worlds from the selected world in which the selected objects exist from the start: what
    they touch is simulated anew, everything else replays the world (Esc cancels; finished worlds stay)"""
    bl_idname = "mwb.add_to_worlds"
    bl_label = "Add Selected to Worlds"
    starter = staticmethod(start_adding)


class MWB_OT_remove_from_worlds(ChangesWorldObjects, bpy.types.Operator):
    """New worlds from the selected world without the selected objects, and without objects deleted
    from the scene since: what they touched is simulated anew (Esc cancels; finished worlds stay)"""
    bl_idname = "mwb.remove_from_worlds"
    bl_label = "Remove from Worlds"
    starter = staticmethod(start_removing)


class MWB_OT_update_in_worlds(ChangesWorldObjects, bpy.types.Operator):
    """New worlds from the selected world in which the selected objects start as they are now (moved
    or changed since): their old bodies leave, new ones start from the first frame, what either
    touches is simulated anew (Esc cancels; finished worlds stay)"""
    bl_idname = "mwb.update_in_worlds"
    bl_label = "Update Selected in Worlds"
    starter = staticmethod(start_updating)


classes = (MWB_OT_add_to_worlds, MWB_OT_remove_from_worlds, MWB_OT_update_in_worlds)
