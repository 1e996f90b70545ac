"""Browsing a library: what follows its opening, keeping the world list in step with it, selecting worlds."""
import os

import bpy

from .. import preview, props, scene_boxes
from ..core import libraries, reactions
from ..core.session import SESSION


def tag_redraw_all():
    wm = bpy.context.window_manager
    for window in (wm.windows if wm else []):
        for area in window.screen.areas:
            area.tag_redraw()


def sync_world_list(scene):
    """Append the worlds the list does not show yet (the list is saved; the library is the truth)."""
    view = SESSION.view
    settings = scene.mwb
    if view is None:
        return 0
    listed = len(settings.worlds)
    if listed > len(view.world_indices) or any(
            settings.worlds[k].world_index != view.world_indices[k] for k in range(min(listed, 8))):
        # A different or rewritten library: rebuild from scratch.
        settings.worlds.clear()
        listed = 0
    for world in view.world_indices[listed:]:
        item = settings.worlds.add()
        item.world_index = world
        summary = view.world_summary(world)
        item.rest_s = summary["rest_s"]
        item.collisions = summary["collisions"]
        item.travel_m = summary["travel_m"]
    return len(view.world_indices) - listed


def on_library_opened(scene, view):
    """Once the library service opened `view` (reactions.LIBRARY_OPENED): list its worlds, apply
    the scene's saved boxes (the path index fills in the background and the boxes follow it), and
    restore the selection."""
    if scene is None:
        return
    sync_world_list(scene)
    scene_boxes.refresh(scene)
    settings = scene.mwb
    if settings.selected_world in view.world_indices:
        # Set the index without its update callback re-entering the preview.
        index = view.world_indices.index(settings.selected_world)
        if settings.world_list_index != index:
            settings["world_list_index"] = index
        if settings.previewing:
            preview.apply(scene)


def open_scene_library(scene):
    """Open (or reopen) the scene's library and restore the selection; False if there is none yet."""
    return libraries.open_library(props.resolved_library_path(scene), scene)


def on_library_chosen(scene):
    """The Libraries list chose another library (reactions.LIBRARY_CHOSEN): browse it."""
    open_scene_library(scene)
    count = len(SESSION.view.world_indices) if SESSION.view else 0
    SESSION.status = f"Opened {os.path.basename(props.resolved_library_path(scene))}: {count} worlds"
    SESSION.last_error = ""


def on_world_selected(scene):
    """The Worlds list selected a world (reactions.WORLD_SELECTED): preview it."""
    preview.begin(scene)


def subscribe_reactions():
    reactions.subscribe(reactions.LIBRARY_OPENED, on_library_opened)
    reactions.subscribe(reactions.LIBRARY_CHOSEN, on_library_chosen)
    reactions.subscribe(reactions.WORLD_SELECTED, on_world_selected)
    reactions.subscribe(reactions.BOXES_CHANGED, scene_boxes.refresh)


class MWB_OT_open_library(bpy.types.Operator):
    """Open the scene's library file and list its worlds"""
    bl_idname = "mwb.open_library"
    bl_label = "Open Library"

    def execute(self, context):
        try:
            found = open_scene_library(context.scene)
        except (IOError, ValueError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        if not found:
            self.report({"WARNING"}, f"No library at {props.resolved_library_path(context.scene) or '(unsaved file)'}")
            return {"CANCELLED"}
        tag_redraw_all()
        return {"FINISHED"}


class MWB_OT_select_world(bpy.types.Operator):
    """Preview one world (by its index in the library)"""
    bl_idname = "mwb.select_world"
    bl_label = "Select World"
    bl_options = {"REGISTER", "UNDO"}

    world: bpy.props.IntProperty(name="World", default=0)

    @classmethod
    def poll(cls, context):
        return SESSION.view is not None

    def execute(self, context):
        view = SESSION.view
        if self.world not in view.world_indices:
            self.report({"ERROR"}, f"World {self.world} is not in the library")
            return {"CANCELLED"}
        # The list index's update callback sets selected_world and starts the preview.
        context.scene.mwb.world_list_index = view.world_indices.index(self.world)
        return {"FINISHED"}


class MWB_OT_go_to_parent(bpy.types.Operator):
    """Preview the world the selected world was refined from"""
    bl_idname = "mwb.go_to_parent"
    bl_label = "Go to Parent"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        view = SESSION.view
        world = context.scene.mwb.selected_world
        return view is not None and world in view.world_indices and view.lineages()[world].parent >= 0

    def execute(self, context):
        view = SESSION.view
        parent = view.lineages()[context.scene.mwb.selected_world].parent
        if parent not in view.world_indices:
            self.report({"ERROR"}, f"The parent world {parent} is not in the library")
            return {"CANCELLED"}
        context.scene.mwb.world_list_index = view.world_indices.index(parent)
        return {"FINISHED"}


def stepped_world(ranked, world, step):
    """The world `step` rows from `world` in the ranked worlds, wrapping round; from a world the
    ranking lacks, the first (forward) or last (backward). None when nothing is ranked."""
    ranked = [int(w) for w in ranked]
    if not ranked:
        return None
    if world not in ranked:
        return ranked[0] if step > 0 else ranked[-1]
    return ranked[(ranked.index(world) + step) % len(ranked)]


class MWB_OT_step_world(bpy.types.Operator):
    """Preview the next (or previous) world of the ranking; works while the timeline plays"""
    bl_idname = "mwb.step_world"
    bl_label = "Step World"
    # Undoable, but with no redo panel: there is nothing to adjust, and the panel would cover the
    # viewport's label of the world stepped to.
    bl_options = {"UNDO"}

    step: bpy.props.IntProperty(name="Step", default=1, description="Rows down the ranking (negative: up)")

    @classmethod
    def poll(cls, context):
        return SESSION.view is not None

    def execute(self, context):
        settings = context.scene.mwb
        ranking = scene_boxes.RANKING.get(context)
        world = stepped_world(ranking.ids, settings.selected_world, self.step)
        if world is None:
            self.report({"WARNING"}, "No world is ranked")
            return {"CANCELLED"}
        settings.world_list_index = SESSION.view.world_indices.index(world)
        row = ranking.position[world]
        self.report({"INFO"}, f"World {world}: {row + 1} of {len(ranking.ids)} in the ranking")
        return {"FINISHED"}


classes = (MWB_OT_open_library, MWB_OT_select_world, MWB_OT_go_to_parent, MWB_OT_step_world)
