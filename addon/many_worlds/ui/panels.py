"""Panels: sampling and worlds in the 3D View sidebar, variation ranges next to the Rigid Body
settings in the Physics properties (where the user already sets the body up)."""
import textwrap

import bpy

from .. import props, scene_boxes
from . import filmstrip, legend, lists
from ..core import library_query
from ..core.export_warnings import grouped_warning_lines
from ..operators import sampling
from ..core.session import SESSION


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


def wrapped_labels(layout, context, text, icon):
    """A long message as lines that fit the region's width (a label is cut, not wrapped)."""
    scale = context.preferences.view.ui_scale
    # At most 8 pixels per character of the UI font at scale 1; the icon takes the first line's
    # start. A popup of the panel is narrower than the region it opens over.
    pixels = min(context.region.width, 230 * scale) if context.region else 230 * scale
    width = max(16, int((pixels - 40 * scale) / (8 * scale)))
    column = layout.column(align=True)
    for k, line in enumerate(textwrap.wrap(text, width) or [""]):
        column.label(text=line, icon=icon if k == 0 else "BLANK1")


class MWB_PT_sampling(SidebarPanel, bpy.types.Panel):
    bl_label = "Sampling"
    bl_idname = "MWB_PT_sampling"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.use_property_split = True
        layout.prop(settings, "library_path")
        if not settings.library_path:
            layout.label(text=props.resolved_library_path(context.scene) or "Save the .blend to choose a default",
                         icon="FILE")
        if len(settings.libraries) > 1:
            layout.template_list("MWB_UL_libraries", "", settings, "libraries", settings, "library_index", rows=2)
        interrupted = sampling.interrupted_run(context.scene)
        if interrupted is not None and SESSION.engine is None:
            layout.label(text=f"Worlds {interrupted[0]} to {interrupted[1] - 1} were cancelled", icon="PAUSE")
        col = layout.column(align=True)
        col.prop(settings, "world_count")
        col.prop(settings, "seed")
        col = layout.column(align=True)
        col.prop(settings, "stop_at_rest")
        col.prop(settings, "duration_s")
        col.prop(settings, "alpha")
        col = layout.column(align=True)
        col.prop(settings, "position_error_mm")
        col.prop(settings, "rotation_error_deg")
        col.prop(settings, "threads")
        row = layout.row(align=True)
        if SESSION.engine is None:
            row.operator("mwb.sample", icon="PLAY")
            row.operator("mwb.check_scene", text="", icon="VIEWZOOM")
        else:
            row.operator("mwb.cancel_sampling", text=f"Cancel {SESSION.run_label}", icon="CANCEL")
        if SESSION.status:
            wrapped_labels(layout, context, SESSION.status, "INFO")
        if SESSION.last_error:
            wrapped_labels(layout, context, SESSION.last_error, "ERROR")
        if SESSION.export_warnings:
            # What the engine does not reproduce as Blender would, named by object and setting.
            box = layout.box()
            box.label(text=f"{len(SESSION.export_warnings)} settings differ from Blender", icon="ERROR")
            for line in grouped_warning_lines(SESSION.export_warnings):
                wrapped_labels(box, context, line, "DOT")


class MWB_PT_worlds(SidebarPanel, bpy.types.Panel):
    bl_label = "Worlds"
    bl_idname = "MWB_PT_worlds"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        view = SESSION.view
        if view is None:
            layout.operator("mwb.open_library", icon="FILE_FOLDER")
            return
        matching = int(view.matching.sum())
        layout.label(text=f"{len(view.world_indices)} worlds, {matching} matching, "
                          f"{len(view.library.rejections)} rejected")
        layout.template_list("MWB_UL_worlds", "", settings, "worlds", settings, "world_list_index", rows=6)
        row = layout.row(align=True)
        row.prop(settings, "family_only", toggle=True, icon="OUTLINER")
        row.operator("mwb.go_to_parent", icon="TRIA_UP")
        row = layout.row(align=True)
        row.prop(settings, "show_paths")
        row.prop(settings, "path_width")
        layout.prop(settings, "path_bodies")
        legend.draw_legend(layout, context)
        row = layout.row(align=True)
        row.operator("mwb.end_preview", icon="LOOP_BACK")
        row.operator("mwb.bake_world", icon="KEYINGSET")


class MWB_PT_refine(LibraryPanel, bpy.types.Panel):
    bl_label = "Refine"
    bl_idname = "MWB_PT_refine"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.use_property_split = True
        layout.prop(settings, "refine_count")
        if SESSION.engine is None:
            layout.operator("mwb.refine_box", icon="SELECT_SET")
            world = settings.selected_world
            layout.label(text=f"Objects selected in world {world}, then drag over the path to change"
                         if world >= 0 else "Select a world and objects first", icon="MOUSE_LMB_DRAG")
            col = layout.column(align=True)
            col.operator("mwb.add_to_worlds", icon="ADD")
            col.operator("mwb.remove_from_worlds", icon="REMOVE")
            col.operator("mwb.update_in_worlds", icon="FILE_REFRESH")
            col = layout.column(align=True)
            col.label(text="New worlds of this one with the selected objects", icon="INFO")
            col.label(text="from the start, without them (and deleted ones),")
            col.label(text="or starting as they are now")
        else:
            layout.operator("mwb.cancel_sampling", text=f"Cancel {SESSION.run_label}", icon="CANCEL")
            layout.label(text=SESSION.status, icon="INFO")


class MWB_PT_query(SidebarPanel, bpy.types.Panel):
    bl_label = "Query Boxes"
    bl_idname = "MWB_PT_query"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        text = scene_boxes.match_text()
        if text:
            layout.label(text=text, icon="FILTER")
        row = layout.row(align=True)
        row.operator("mwb.draw_box", icon="SELECT_SET").negative = False
        row.operator("mwb.draw_box", text="Negative", icon="SELECT_SUBTRACT").negative = True
        layout.label(text="Ctrl+Alt+drag; with Shift: negative", icon="MOUSE_LMB_DRAG")
        row = layout.row()
        row.template_list("MWB_UL_boxes", "", settings, "boxes", settings, "box_index", rows=3)
        row.operator("mwb.clear_boxes", text="", icon="TRASH")
        if 0 <= settings.box_index < len(settings.boxes):
            box = settings.boxes[settings.box_index]
            col = layout.column(align=True)
            row = col.row(align=True)
            row.label(text="Bodies: " + (", ".join(b.name for b in box.bodies) or "none"))
            row.operator("mwb.box_use_selected", text="", icon="RESTRICT_SELECT_OFF").index = settings.box_index
            row = col.row(align=True)
            row.prop(box, "use_time_window")
            sub = row.row(align=True)
            sub.active = box.use_time_window
            sub.prop(box, "time_start_s")
            sub.prop(box, "time_end_s")
            row = col.row(align=True)
            row.prop(box, "swept")
            row.prop(box, "after")
        self.draw_seek(context, layout)

    @staticmethod
    def draw_seek(context, layout):
        """Goal search: every enabled box, in its order, by refining worlds."""
        settings = context.scene.mwb
        layout.separator()
        col = layout.column(align=True)
        col.prop(settings, "seek_want")
        col.prop(settings, "seek_budget_worlds")
        col.prop(settings, "seek_budget_s")
        if SESSION.engine is None:
            layout.operator("mwb.seek", icon="VIEWZOOM")
        else:
            layout.operator("mwb.cancel_sampling", text=f"Cancel {SESSION.run_label}", icon="CANCEL")
        if SESSION.run_label == "Seeking":
            if SESSION.last_error:
                wrapped_labels(layout, context, SESSION.last_error, "ERROR")
            elif SESSION.status:
                wrapped_labels(layout, context, SESSION.status, "INFO")


class MWB_PT_ranking(LibraryPanel, bpy.types.Panel):
    bl_label = "Ranking"
    bl_idname = "MWB_PT_ranking"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        row = layout.row(align=True)
        row.prop(settings, "rank_metric", text="")
        row.prop(settings, "rank_descending", text="", icon="SORT_DESC" if settings.rank_descending else "SORT_ASC")
        if settings.rank_metric != library_query.BOXES_MET:
            row = layout.row(align=True)
            row.prop(settings, "rank_combine", expand=True)
            row = layout.row(align=True)
            row.prop(settings, "rank_bodies", text="")
            row.operator("mwb.rank_use_selected", text="", icon="RESTRICT_SELECT_OFF")
            if settings.rank_bodies == "LISTED":
                layout.label(text=", ".join(b.name for b in settings.rank_body_names) or "no bodies")
        rank, world, value = lists.ranking_columns(layout.row())
        rank.label(text="#")
        world.label(text="World")
        value.label(text=settings.bl_rna.properties["rank_metric"].enum_items[settings.rank_metric].name)
        # Same collection and active index as the Worlds list: clicking a row previews the world.
        layout.template_list("MWB_UL_ranking", "", settings, "worlds", settings, "world_list_index", rows=8)
        filmstrip.draw_filmstrip(layout, context)


class MWB_PT_object_variation(bpy.types.Panel):
    bl_label = "Many Worlds Variation"
    bl_idname = "MWB_PT_object_variation"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.rigid_body is not None

    def draw(self, context):
        layout = self.layout
        v = context.object.mwb_variation
        for low, high in (("location_min", "location_max"), ("rotation_min", "rotation_max"),
                          ("linear_velocity_min", "linear_velocity_max"),
                          ("angular_velocity_min", "angular_velocity_max")):
            row = layout.row()
            row.column().prop(v, low)
            row.column().prop(v, high)


classes = (MWB_PT_sampling, MWB_PT_worlds, MWB_PT_refine, MWB_PT_query, MWB_PT_ranking,
           MWB_PT_object_variation)
