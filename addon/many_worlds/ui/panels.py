"""Panels. The 3D View sidebar follows the workflow, top to bottom: Sample, Boxes (and Seek),
Worlds & Ranking, Refine, Bake; settings only an expert changes sit in collapsed subpanels. The
variation ranges are a subpanel of Blender's Rigid Body Settings in the Physics properties, right
under the mass and the Dynamic and Animated switches, where the user already sets the body up."""
import os

import bpy

from .. import pose_parts, preview, props, scene_boxes
from . import filmstrip, fit, legend, lists
from .fit import wrapped_labels
from ..core import library_query, pose_target
from ..core.export_warnings import grouped_warning_lines
from ..operators import sampling, seeking
from ..core.run import RunKind
from ..core.session import SESSION
from ..draw import paths as path_overlay


class SidebarPanel:
    """Placement of the add-on's panels: the 3D view's sidebar, tab "Many Worlds"."""
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Many Worlds"


class LibraryPanel(SidebarPanel):
    """A sidebar panel that only makes sense while a library is open."""

    @classmethod
    def poll(cls, context):
        return SESSION.view is not None


def cancel_button(layout):
    layout.operator("mwb.cancel_sampling", text=f"Cancel {SESSION.run.label}", icon="CANCEL")


# --- 1. Sample -----------------------------------------------------------------------------------

class MWB_PT_sampling(SidebarPanel, bpy.types.Panel):
    bl_label = "Sample"
    bl_idname = "MWB_PT_sampling"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.prop(settings, "library_path", text="")
        path = props.resolved_library_path(context.scene)
        if path and not settings.library_path:
            wrapped_labels(layout, context, f"Writes to {os.path.basename(path)}", "FILE")
        if len(settings.libraries) > 1:
            layout.template_list("MWB_UL_libraries", "", settings, "libraries", settings, "library_index", rows=2)
        interrupted = sampling.interrupted_run(context.scene)
        if interrupted is not None and SESSION.run is None:
            wrapped_labels(layout, context, f"Worlds {interrupted[0]} to {interrupted[1] - 1} were cancelled",
                           "PAUSE")
        col = layout.column(align=True)
        col.prop(settings, "world_count")
        col.prop(settings, "seed")
        col = layout.column(align=True)
        col.prop(settings, "stop_at_rest")
        col.prop(settings, "duration_s")
        row = layout.row(align=True)
        row.scale_y = 1.4
        if SESSION.run is None:
            row.operator("mwb.sample", icon="PLAY")
            row.operator("mwb.check_scene", text="", icon="VIEWZOOM")
            # A greyed-out button says why, here as in its tooltip.
            blocker = sampling.sample_blocker(context.scene)
            if blocker:
                wrapped_labels(layout, context, blocker, "ERROR")
        else:
            cancel_button(row)
        if SESSION.status and SESSION.last_kind != RunKind.SEEK:
            wrapped_labels(layout, context, SESSION.status, "INFO")
        if SESSION.last_error and SESSION.last_kind != RunKind.SEEK:
            wrapped_labels(layout, context, SESSION.last_error, "ERROR")
        if SESSION.export_warnings:
            # What the engine does not reproduce as Blender would, named by object and setting.
            box = layout.box()
            wrapped_labels(box, context, f"{len(SESSION.export_warnings)} settings differ from Blender", "ERROR")
            # Folded by setting; Sample and Check Scene report every line (Info editor).
            constraints = {ob.name for ob in context.scene.objects if ob.rigid_body_constraint is not None}
            for line in grouped_warning_lines(SESSION.export_warnings, constraints=constraints):
                wrapped_labels(box, context, line, "DOT")


class MWB_PT_sampling_expert(SidebarPanel, bpy.types.Panel):
    bl_label = "Expert Settings"
    bl_idname = "MWB_PT_sampling_expert"
    bl_parent_id = "MWB_PT_sampling"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.prop(settings, "alpha")
        col = layout.column(align=True)
        col.prop(settings, "position_error_mm")
        col.prop(settings, "rotation_error_deg")
        layout.prop(settings, "threads")


# --- 2. Boxes and Seek ---------------------------------------------------------------------------

# The kinds of goal parts: a box drawn on screen, a pose of an object's own axes.
BOX_ICON = "SELECT_SET"
POSE_ICON = "ORIENTATION_LOCAL"


class MWB_PT_query(SidebarPanel, bpy.types.Panel):
    bl_label = "Boxes"
    bl_idname = "MWB_PT_query"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        if SESSION.goal_problem:
            # In place of the match count: no part filters the worlds until the refused one is mended.
            wrapped_labels(layout, context, SESSION.goal_problem, "ERROR")
        else:
            text = scene_boxes.match_text()
            if text:
                wrapped_labels(layout, context, text, "FILTER")
        progress = scene_boxes.index_progress_text()
        if progress:
            wrapped_labels(layout, context, progress, "TIME")
        self.draw_new_box_bodies(context, layout)
        if SESSION.box_note:
            wrapped_labels(layout, context, SESSION.box_note, "ERROR")
        col = layout.column(align=True)
        row = col.row(align=True)
        row.operator("mwb.draw_box", text="Draw Box", icon=BOX_ICON).negative = False
        row.operator("mwb.draw_box", text="Negative", icon="SELECT_SUBTRACT").negative = True
        col.operator("mwb.add_pose", text="Add Pose", icon=POSE_ICON)
        # A greyed-out Add Pose says why, here as in its tooltip.
        problem = scene_boxes.new_pose_problem(context)
        if problem:
            wrapped_labels(layout, context, problem, "ERROR")
        wrapped_labels(layout, context, "Or Ctrl+Alt+drag in the viewport to draw a box (with Shift: negative)",
                       "MOUSE_LMB_DRAG")
        layout.template_list("MWB_UL_boxes", "", settings, "boxes", settings, "box_index", rows=3)
        if 0 <= settings.box_index < len(settings.boxes):
            part = settings.boxes[settings.box_index]
            draw = self.draw_active_pose if part.kind == "POSE" else self.draw_active_box
            draw(context, layout, part, settings.box_index)
        if len(settings.boxes):
            layout.operator("mwb.clear_boxes", icon="TRASH")

    @staticmethod
    def draw_new_box_bodies(context, layout):
        """Which objects a box drawn now tests, and the selected ones it leaves out."""
        names, left_out = scene_boxes.body_choice(context)
        if not names:
            wrapped_labels(layout, context, "No simulated rigid bodies to test", "ERROR")
            return
        wrapped_labels(layout, context, f"A new box tests {', '.join(names)}", "OBJECT_DATA")
        if left_out:
            wrapped_labels(layout, context, scene_boxes.left_out_text(left_out), "ERROR")

    @staticmethod
    def draw_active_box(context, layout, box, index):
        bodies = ", ".join(b.name for b in box.bodies) or "no bodies"
        wrapped_labels(layout, context, f"Box {index + 1} tests {bodies}", "SELECT_SET")
        layout.operator("mwb.box_use_selected", icon="RESTRICT_SELECT_OFF").index = index
        col = layout.column(align=True)
        col.prop(box, "use_time_window")
        if not box.use_time_window:
            wrapped_labels(col, context, "Any time: a path that only passes through counts too", "INFO")
        sub = col.column(align=True)
        sub.active = box.use_time_window
        sub.prop(box, "time_start_s")
        sub.prop(box, "time_end_s")
        col = layout.column(align=True)
        col.prop(box, "swept")
        draw_met_after(col, box)

    @staticmethod
    def draw_active_pose(context, layout, part, index):
        bodies = ", ".join(b.name for b in part.bodies) or "no bodies"
        wrapped_labels(layout, context, f"Pose {index + 1} tests {bodies}", POSE_ICON)
        layout.operator("mwb.box_use_selected", icon="RESTRICT_SELECT_OFF").index = index
        layout.row(align=True).prop(part, "pose_mode", expand=True)
        if part.pose_mode == pose_target.AXIS:
            row = layout.row(align=True)
            row.prop(part, "pose_axis", text="")
            row.label(text="towards")
            row.prop(part, "pose_direction", text="")
        elif part.pose_mode == pose_target.AS_POSED:
            layout.operator("mwb.pose_use_current", icon="ARMATURE_DATA").index = index
        wrapped_labels(layout, context, pose_text(part), "INFO")
        layout.prop(part, "within_deg", text="Within (°)")
        now = pose_now_text(part)
        if now:
            wrapped_labels(layout, context, now[0], now[1])
        col = layout.column(align=True)
        if part.negative:
            col.prop(part, "longer_than_s")
        col.prop(part, "use_time_window")
        if not part.use_time_window:
            wrapped_labels(col, context, "No time window: held throughout the run" if not part.negative
                           else "No time window: over the whole run", "INFO")
        sub = col.column(align=True)
        sub.active = part.use_time_window
        sub.prop(part, "time_start_s")
        sub.prop(part, "time_end_s")
        draw_met_after(layout.column(align=True), part)


def draw_met_after(layout, part):
    row = layout.row(align=True)
    row.label(text="Met After")
    row.prop(part, "after", text="")


def pose_text(part):
    """What a pose part keeps, in words: "Keeps worlds where Die's local +Z faces up"."""
    side, direction = pose_target.describe(part.pose_mode, part.pose_axis, part.pose_direction,
                                           tuple(part.pose_captured_axis))
    if side is None:
        return "No pose captured yet: press Use Current Pose"
    names = [item.name for item in part.bodies]
    if not part.negative:
        whose = f"{names[0]}'s" if len(names) == 1 else "each object's"
        return f"Keeps worlds where {whose} {side} faces {direction}"
    whose = f"{names[0]}'s" if len(names) == 1 else "an object's"
    longer = f"for over {part.longer_than_s:.2f}{fit.NO_BREAK_SPACE}s" if part.longer_than_s > 0 else "at any moment"
    return f"Rejects worlds where {whose} {side} faces {direction} {longer}"


def pose_now_text(part):
    """(text, icon): how far the part's objects are from its direction at this frame, ticked when
    that pose is the one the part keeps (all within; for a negative part, none), or None."""
    angles = pose_parts.angles_now(part)
    if not angles:
        return None
    shown = ", ".join(f"{name} {angle:.0f}°" for name, angle in angles[:3])
    more = f" and {len(angles) - 3} more" if len(angles) > 3 else ""
    within = [angle <= part.within_deg for _, angle in angles]
    kept = not any(within) if part.negative else all(within)
    return f"Now: {shown}{more} off", "CHECKMARK" if kept else "CANCEL"


class MWB_PT_seek(SidebarPanel, bpy.types.Panel):
    bl_label = "Seek"
    bl_idname = "MWB_PT_seek"
    bl_parent_id = "MWB_PT_query"

    def draw(self, context):
        """Goal search: every enabled box, in its order, by refining worlds."""
        layout = self.layout
        settings = context.scene.mwb
        col = layout.column(align=True)
        col.prop(settings, "seek_want")
        col.prop(settings, "seek_budget_worlds")
        col.prop(settings, "seek_budget_s")
        if SESSION.run is None:
            layout.operator("mwb.seek", icon="VIEWZOOM")
            problem = seeking.seek_problem(context.scene)
            if problem:
                wrapped_labels(layout, context, problem, "ERROR")
        else:
            cancel_button(layout)
        if SESSION.last_kind == RunKind.SEEK:
            if SESSION.last_error:
                wrapped_labels(layout, context, SESSION.last_error, "ERROR")
            elif SESSION.status:
                wrapped_labels(layout, context, SESSION.status, "INFO")


# --- 3. Worlds & Ranking ---------------------------------------------------------------------------

class MWB_PT_worlds(SidebarPanel, bpy.types.Panel):
    bl_label = "Worlds & Ranking"
    bl_idname = "MWB_PT_worlds"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        view = SESSION.view
        if view is None:
            layout.operator("mwb.open_library", icon="FILE_FOLDER")
            return
        matching = int(view.matching.sum())
        wrapped_labels(layout, context, f"{len(view.world_indices)} worlds, {matching} matching, "
                                        f"{len(view.library.rejections)} rejected", "WORLD")
        self.draw_ranking_settings(context, layout, settings)
        if settings.family_only:
            # The selected world's root, ancestors and children, by generation.
            layout.template_list("MWB_UL_worlds", "", settings, "worlds", settings, "world_list_index", rows=8)
        else:
            rank, world, value = lists.ranking_columns(layout.row())
            rank.label(text="#")
            world.label(text="World")
            value.label(text=settings.bl_rna.properties["rank_metric"].enum_items[settings.rank_metric].name)
            # Same collection and active index as the family list: clicking a row previews the world.
            layout.template_list("MWB_UL_ranking", "", settings, "worlds", settings, "world_list_index", rows=8)
        filmstrip.draw_filmstrip(layout, context)
        row = layout.row(align=True)
        row.prop(settings, "family_only", text="Family", toggle=True, icon="OUTLINER")
        row.operator("mwb.go_to_parent", text="Parent", icon="TRIA_UP")
        self.draw_preview_state(context, layout)

    @staticmethod
    def draw_ranking_settings(context, layout, settings):
        row = layout.row(align=True)
        row.prop(settings, "rank_metric", text="")
        row.prop(settings, "rank_descending", text="", icon="SORT_DESC" if settings.rank_descending else "SORT_ASC")
        if settings.rank_metric == library_query.BOXES_MET:
            return
        row = layout.row(align=True)
        row.prop(settings, "rank_combine", expand=True)
        row = layout.row(align=True)
        row.prop(settings, "rank_bodies", text="")
        row.operator("mwb.rank_use_selected", text="", icon="RESTRICT_SELECT_OFF")
        names = scene_boxes.ranking_body_names(context)
        wrapped_labels(layout, context, "Of " + (", ".join(names) or "no bodies"), "BLANK1")

    @staticmethod
    def draw_preview_state(context, layout):
        """Preview is a state: what it does to the scene, and the way out."""
        state = preview.state_text(context.scene)
        if not state:
            return
        box = layout.box()
        conflict = preview.conflict(context.scene)
        wrapped_labels(box, context, state, "ERROR" if conflict else "HIDE_OFF")
        col = box.column(align=True)
        col.operator("mwb.end_preview", icon="LOOP_BACK")
        if conflict:
            col.operator("mwb.keep_previewing", icon="PLAY")


class MWB_PT_paths(SidebarPanel, bpy.types.Panel):
    bl_label = "Paths"
    bl_idname = "MWB_PT_paths"
    bl_parent_id = "MWB_PT_worlds"

    @classmethod
    def poll(cls, context):
        return SESSION.view is not None

    def draw_header(self, context):
        self.layout.prop(context.scene.mwb, "show_paths", text="")

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.active = settings.show_paths
        layout.prop(settings, "path_width")
        layout.prop(settings, "path_bodies", text="")
        budget = path_overlay.OVERLAY.budget_text()
        if budget and settings.show_paths:
            wrapped_labels(layout, context, budget, "INFO")
        legend.draw_legend(layout, context)


# --- 4. Refine ------------------------------------------------------------------------------------

class MWB_PT_refine(LibraryPanel, bpy.types.Panel):
    bl_label = "Refine"
    bl_idname = "MWB_PT_refine"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.prop(settings, "refine_count")
        if SESSION.run is not None:
            cancel_button(layout)
            wrapped_labels(layout, context, SESSION.status, "INFO")
            return
        layout.operator("mwb.refine_box", icon="SELECT_SET")
        world = settings.selected_world
        wrapped_labels(layout, context, f"Select objects of world {world}, then drag over their paths where "
                                        "they should change" if world >= 0 else "Select a world and objects first",
                       "MOUSE_LMB_DRAG")
        col = layout.column(align=True)
        col.operator("mwb.add_to_worlds", text="Add Selected", icon="ADD")
        col.operator("mwb.remove_from_worlds", text="Remove Selected", icon="REMOVE")
        col.operator("mwb.update_in_worlds", text="Update Selected", icon="FILE_REFRESH")
        wrapped_labels(layout, context, "New worlds of this one: with the selected objects from the start, "
                                        "without them (and deleted ones), or starting as they are now", "INFO")


# --- 5. Bake --------------------------------------------------------------------------------------

class MWB_PT_bake(LibraryPanel, bpy.types.Panel):
    bl_label = "Bake"
    bl_idname = "MWB_PT_bake"

    def draw(self, context):
        layout = self.layout
        world = context.scene.mwb.selected_world
        wrapped_labels(layout, context, f"Keys world {world} onto its objects" if world >= 0
                       else "Select a world to bake", "KEYINGSET")
        row = layout.row()
        row.scale_y = 1.4
        row.operator("mwb.bake_world", icon="KEYINGSET")


# --- Variation, in Physics > Rigid Body ----------------------------------------------------------

VARIATION_ROWS = (
    # (± property, min, max, what the range is around, its unit as the field shows it)
    ("location_pm", "location_min", "location_max", "location"),
    ("rotation_pm", "rotation_min", "rotation_max", "rotation"),
    ("linear_velocity_pm", "linear_velocity_min", "linear_velocity_max", "velocity"),
    ("angular_velocity_pm", "angular_velocity_min_deg", "angular_velocity_max_deg", "spin"),
)


def around_text(scene, ob, quantity):
    """What a range is added to: the object's own location and rotation (not a previewed world's
    pose; in the scene's units), or its starting velocity (a rigid body starts at rest)."""
    units = scene.unit_settings
    matrix = preview.own_matrix(scene, ob)
    if quantity == "location":
        # A coordinate a hair below zero reads 0, not -0 (adding 0.0 drops the sign of -0.0).
        if units.system == "NONE":
            return "Around " + ", ".join(f"{round(v, 2) + 0.0:.2f}" for v in matrix.translation)
        metres = [v * units.scale_length for v in matrix.translation]
        # A value keeps its unit on its line (a no-break space between them).
        values = [bpy.utils.units.to_string(units.system, "LENGTH", v if abs(v) >= 1e-6 else 0.0,
                                            precision=2).replace(" ", fit.NO_BREAK_SPACE) for v in metres]
        return "Around " + ", ".join(values)
    if quantity == "rotation":
        return "Around " + ", ".join(f"{round(v * props.DEG_PER_RAD)}°" for v in matrix.to_euler())
    if quantity == "velocity":
        return "Around rest (m/s)"
    return "Around rest (°/s)"


class MWB_PT_object_variation(bpy.types.Panel):
    bl_label = "Many Worlds Variation"
    bl_idname = "MWB_PT_object_variation"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"
    bl_parent_id = "PHYSICS_PT_rigid_body_settings"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.rigid_body is not None

    def draw(self, context):
        layout = self.layout
        ob = context.object
        v = ob.mwb_variation
        layout.prop(v, "show_min_max")
        for plus_minus, low, high, quantity in VARIATION_ROWS:
            col = layout.column(align=True)
            col.label(text=v.bl_rna.properties[plus_minus].name)
            wrapped_labels(col, context, around_text(context.scene, ob, quantity), "BLANK1")
            if v.show_min_max:
                row = col.row(align=True)
                row.column(align=True).prop(v, low, text="Min")
                row.column(align=True).prop(v, high, text="Max")
            else:
                col.column(align=True).prop(v, plus_minus, text="")


classes = (MWB_PT_sampling, MWB_PT_sampling_expert, MWB_PT_query, MWB_PT_seek, MWB_PT_worlds, MWB_PT_paths,
           MWB_PT_refine, MWB_PT_bake, MWB_PT_object_variation)
