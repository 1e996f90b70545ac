"""Properties saved with the .blend: per-object variation ranges and per-scene sampling and
browsing state. Runtime objects (open library, engine process) live in core.session."""
import bpy
from bpy.props import (BoolProperty, CollectionProperty, EnumProperty, FloatProperty, FloatVectorProperty,
                       IntProperty, PointerProperty, StringProperty)


def _vector(name, subtype, description, unit="NONE"):
    return FloatVectorProperty(name=name, size=3, subtype=subtype, unit=unit, description=description)


class MWB_ObjectVariation(bpy.types.PropertyGroup):
    """Uniform ranges added to the object's initial state, per sampled world."""
    location_min: _vector("Location Min", "TRANSLATION", "Lowest offset added to the initial location", "LENGTH")
    location_max: _vector("Location Max", "TRANSLATION", "Highest offset added to the initial location", "LENGTH")
    rotation_min: _vector("Rotation Min", "EULER", "Lowest XYZ Euler rotation added to the initial pose")
    rotation_max: _vector("Rotation Max", "EULER", "Highest XYZ Euler rotation added to the initial pose")
    linear_velocity_min: _vector("Velocity Min", "VELOCITY", "Lowest initial linear velocity (m/s, world)")
    linear_velocity_max: _vector("Velocity Max", "VELOCITY", "Highest initial linear velocity (m/s, world)")
    angular_velocity_min: _vector("Angular Velocity Min", "XYZ", "Lowest initial angular velocity (rad/s, world)")
    angular_velocity_max: _vector("Angular Velocity Max", "XYZ", "Highest initial angular velocity (rad/s, world)")


class MWB_WorldItem(bpy.types.PropertyGroup):
    """One stored world as listed in the panel."""
    world_index: IntProperty(name="World")
    rest_s: FloatProperty(name="Rest", description="Time until the last body came to rest", unit="TIME_ABSOLUTE")
    collisions: IntProperty(name="Collisions", description="Collisions of the simulated bodies")
    travel_m: FloatProperty(name="Travel", description="Summed path length of the simulated bodies", unit="LENGTH")


class MWB_SavedTransform(bpy.types.PropertyGroup):
    """An object's own transform from before previewing, to put back when the preview ends."""
    target: PointerProperty(type=bpy.types.Object)
    matrix_basis: FloatVectorProperty(size=16)


def _on_world_list_index(self, context):
    # Selecting a row previews that world; the import is late to keep modules free of cycles.
    from . import preview
    if 0 <= self.world_list_index < len(self.worlds):
        self.selected_world = self.worlds[self.world_list_index].world_index
        preview.begin(context.scene)
    for area in (context.screen.areas if context.screen else []):
        area.tag_redraw()


def _tag_redraw(self, context):
    for area in (context.screen.areas if context.screen else []):
        area.tag_redraw()


class MWB_SceneSettings(bpy.types.PropertyGroup):
    # Sampling
    library_path: StringProperty(
        name="Library", subtype="FILE_PATH",
        description="Library file (.mwb) the worlds are written to; empty: <blend name>.mwb next to the .blend")
    world_count: IntProperty(name="Worlds", default=100, min=1, soft_max=10000,
                             description="Worlds to add per press of Sample")
    seed: IntProperty(name="Seed", default=0, min=0, description="Base seed: a world is a function of seed and index")
    stop_at_rest: BoolProperty(name="Until Rest", default=True,
                               description="End a world when every body has rested for a while")
    duration_s: FloatProperty(name="Duration", default=0.0, min=0.0, unit="TIME_ABSOLUTE",
                              description="Simulated seconds per world; 0: the rigid body world's frame range")
    alpha: FloatProperty(name="Perturbation", default=0.1, min=0.0, max=0.4,
                         description="Strength of the random change at each impact (alpha, fraction of |dv|)")
    position_error_mm: FloatProperty(name="Position Error", default=1.0, min=0.01, soft_max=10.0,
                                     description="Largest stored position error, millimetres")
    rotation_error_deg: FloatProperty(name="Rotation Error", default=0.5, min=0.01, soft_max=5.0,
                                      description="Largest stored rotation error, degrees")
    threads: IntProperty(name="Threads", default=0, min=0, description="Engine threads; 0: all cores")
    # Browsing
    worlds: CollectionProperty(type=MWB_WorldItem)
    world_list_index: IntProperty(name="World", default=-1, update=_on_world_list_index)
    selected_world: IntProperty(name="Selected World", default=-1,
                                description="Index of the world being previewed; -1: none")
    show_paths: BoolProperty(name="Show Paths", default=True, update=_tag_redraw)
    path_bodies: EnumProperty(
        name="Paths Of", default="ACTIVE", update=_tag_redraw,
        items=[("ACTIVE", "Simulated Bodies", "Paths of every body the simulation moves"),
               ("SELECTED", "Selected Objects", "Paths of the selected objects only")])
    path_width: FloatProperty(name="Width", default=2.0, min=1.0, max=10.0, update=_tag_redraw)
    # Preview: what to put back when it ends (saved, so a reload mid-preview can still restore).
    previewing: BoolProperty(default=False)
    preview_rigidbody_enabled: BoolProperty(default=True)
    preview_saved: CollectionProperty(type=MWB_SavedTransform)


classes = (MWB_ObjectVariation, MWB_WorldItem, MWB_SavedTransform, MWB_SceneSettings)


def register_properties():
    bpy.types.Object.mwb_variation = PointerProperty(type=MWB_ObjectVariation)
    bpy.types.Scene.mwb = PointerProperty(type=MWB_SceneSettings)


def unregister_properties():
    del bpy.types.Scene.mwb
    del bpy.types.Object.mwb_variation


def resolved_library_path(scene):
    """Absolute library path: the property, else <blend name>.mwb next to the saved .blend, else ''."""
    from .core.paths import default_library_name
    path = scene.mwb.library_path or ("//" + default_library_name(bpy.data.filepath) if bpy.data.filepath else "")
    return bpy.path.abspath(path) if path else ""


