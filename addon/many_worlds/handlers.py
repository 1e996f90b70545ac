"""Application handlers: restoring the browsing state on load and after undo, the preview on
frame change, and noticing edits made during a preview."""
import bpy

from . import preview, props, scene_boxes
from .core.session import SESSION
from .draw import paths
from .operators import browsing


@bpy.app.handlers.persistent
def on_load_post(*_args):
    # A different file: the old library, engine and caches belong to the previous one.
    from .operators import run_poller
    run_poller.stop_for_unregister()
    SESSION.close()
    paths.OVERLAY.clear()
    preview.forget()
    for ob in bpy.data.objects:
        props.upgrade_saved_variation(ob)
    scene = bpy.context.scene
    try:
        browsing.open_scene_library(scene)
    except (IOError, ValueError) as error:
        SESSION.last_error = f"Could not reopen the library: {error}"


@bpy.app.handlers.persistent
def on_undo_redo(*_args):
    # Undo restores the boxes (scene properties) but not the runtime match flags: recompute.
    if SESSION.view is not None:
        scene_boxes.refresh(bpy.context.scene)


_HANDLERS = ((bpy.app.handlers.load_post, on_load_post),
             (bpy.app.handlers.frame_change_pre, preview.on_frame_change),
             (bpy.app.handlers.depsgraph_update_post, preview.on_depsgraph_update),
             (bpy.app.handlers.undo_post, on_undo_redo),
             (bpy.app.handlers.redo_post, on_undo_redo))


def add():
    for handler_list, function in _HANDLERS:
        if function not in handler_list:
            handler_list.append(function)


def remove():
    for handler_list, function in _HANDLERS:
        while function in handler_list:
            handler_list.remove(function)


classes = ()
