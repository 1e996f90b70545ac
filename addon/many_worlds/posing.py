"""Posing the scene as a world has it at one recorded frame, for a picture of that moment, and
putting it back: thumbnails in the panel and the command line's contact sheet both pose this way.

Each simulated object present in the world is moved to its pose there; an object whose body the
world lacks is hidden. The scene's rigid body world is switched off meanwhile, or Blender's own
simulation would move the objects back. Everything is restored when the `with` block ends. The
add-on's own depsgraph handlers (which watch for the user's edits during a preview) are held back
meanwhile: the pose is no edit.
"""
import contextlib

import numpy as np
from mathutils import Matrix, Quaternion, Vector


def last_frame(library, world):
    """The world's last recorded frame (where it came to rest, or the end of the run)."""
    return int(library.frame_count(world)) - 1


def filmstrip_frames(frame_count, count=5):
    """`count` recorded frames spread over a world of `frame_count` frames, first and last included."""
    if frame_count < 1:
        return []
    return sorted(set(int(f) for f in np.round(np.linspace(0, frame_count - 1, count))))


def world_pose(library, world, frame, bodies):
    """{body index: (location (3,), quaternion (4,) w first)} of those of `bodies` present in
    `world` at recorded `frame` (clamped to the world's frames)."""
    frame = int(np.clip(frame, 0, library.frame_count(world) - 1))
    present = library.present(world)
    return {b: library.pose(world, b, frame) for b in bodies if b < len(present) and present[b]}


@contextlib.contextmanager
def own_depsgraph_handlers_held():
    """Within the block, this add-on's depsgraph update handlers are not called."""
    import bpy
    handlers = bpy.app.handlers.depsgraph_update_post
    package = __package__ or __name__.rpartition(".")[0]
    held = [f for f in handlers if getattr(f, "__module__", "").startswith(package + ".")]
    for function in held:
        handlers.remove(function)
    try:
        yield
    finally:
        for function in held:
            if function not in handlers:
                handlers.append(function)


@contextlib.contextmanager
def posed(scene, view_layer, view, world, frame, hide_render=False):
    """Within the block, the scene's objects stand as `world` has them at recorded `frame`.

    view: core.library_view.LibraryView. The view layer is evaluated after posing and after
    restoring. hide_render: also hide absent objects from rendering (the command line renders).
    """
    import bpy
    with own_depsgraph_handlers_held():
        with _posed(bpy, scene, view_layer, view, world, frame, hide_render):
            yield


@contextlib.contextmanager
def _posed(bpy, scene, view_layer, view, world, frame, hide_render):
    simulated = set(view.simulated_bodies())
    pose = world_pose(view.library, world, frame, simulated)
    moved, hidden = [], []
    for name, body in view.object_bodies(world).items():
        ob = bpy.data.objects.get(name)
        if ob is None or body not in simulated:
            continue
        if body not in pose:
            hidden.append((ob, ob.hide_get(view_layer=view_layer), ob.hide_render))
            ob.hide_set(True, view_layer=view_layer)
            if hide_render:
                ob.hide_render = True
            continue
        moved.append((ob, ob.matrix_world.copy()))
        location, rotation = pose[body]
        scale = ob.matrix_world.to_scale()
        ob.matrix_world = Matrix.LocRotScale(Vector(location), Quaternion(rotation), scale)
    rbw = scene.rigidbody_world
    rigid_body_enabled = rbw is not None and rbw.enabled
    if rigid_body_enabled:
        rbw.enabled = False
    view_layer.update()
    try:
        yield
    finally:
        for ob, matrix in moved:
            ob.matrix_world = matrix
        for ob, was_hidden, was_hidden_render in hidden:
            ob.hide_set(was_hidden, view_layer=view_layer)
            ob.hide_render = was_hidden_render
        if rigid_body_enabled:
            rbw.enabled = True
        view_layer.update()
