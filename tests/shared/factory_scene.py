"""An empty factory scene with the add-on registered, for the suites that run inside Blender."""
import contextlib


@contextlib.contextmanager
def factory_scene_with_addon():
    """Read Blender's factory settings (no objects), register the add-on, and unregister it after."""
    import bpy
    import many_worlds
    bpy.ops.wm.read_factory_settings(use_empty=True)
    many_worlds.register()
    yield bpy.context.scene
    many_worlds.unregister()
