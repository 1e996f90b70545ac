"""Panels: sampling and worlds in the 3D View sidebar, variation ranges next to the Rigid Body
settings in the Physics properties (where the user already sets the body up)."""
import bpy

from .. import props
from ..core.session import SESSION


class MWB_PT_sampling(bpy.types.Panel):
    bl_label = "Sampling"
    bl_idname = "MWB_PT_sampling"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Many Worlds"

    def draw(self, context):
        layout = self.layout
        settings = context.scene.mwb
        layout.use_property_split = True
        layout.prop(settings, "library_path")
        if not settings.library_path:
            layout.label(text=props.resolved_library_path(context.scene) or "Save the .blend to choose a default",
                         icon="FILE")
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
            row.operator("mwb.cancel_sampling", icon="CANCEL")
        if SESSION.status:
            layout.label(text=SESSION.status, icon="INFO")
        if SESSION.last_error:
            layout.label(text=SESSION.last_error, icon="ERROR")


class MWB_PT_worlds(bpy.types.Panel):
    bl_label = "Worlds"
    bl_idname = "MWB_PT_worlds"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Many Worlds"

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
        row.prop(settings, "show_paths")
        row.prop(settings, "path_width")
        layout.prop(settings, "path_bodies")
        row = layout.row(align=True)
        row.operator("mwb.end_preview", icon="LOOP_BACK")
        row.operator("mwb.bake_world", icon="KEYINGSET")


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


classes = (MWB_PT_sampling, MWB_PT_worlds, MWB_PT_object_variation)
