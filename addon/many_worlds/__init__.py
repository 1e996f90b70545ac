"""Many-Worlds Browser: sample many plausible outcomes of a rigid-body scene, browse and bake one.

Blender modules are imported inside register()/unregister() so that `many_worlds._native` and
`many_worlds.core` also import in a plain Python (tests, farm scripts) where bpy does not exist.
"""
bl_info = {
    "name": "Many-Worlds Browser",
    "author": "Many-Worlds Browser authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D View > Sidebar > Many Worlds; Properties > Physics",
    "description": "Sample thousands of plausible rigid-body outcomes, browse their paths, bake one",
    "category": "Physics",
}


def _modules():
    from . import bake, draw, export, operators, preview, props, ui
    return (props, export, preview, bake, operators, ui, draw)


def _classes():
    return [cls for module in _modules() for cls in module.classes]


def register():
    import bpy
    from . import draw, handlers, keymaps, props
    for cls in _classes():
        bpy.utils.register_class(cls)
    props.register_properties()
    from .operators import browsing
    browsing.subscribe_reactions()
    handlers.add()
    draw.add_handlers()
    keymaps.add()
    from . import compat
    compat.register_cli_command(__name__)


def unregister():
    import bpy
    from . import draw, handlers, keymaps, preview, props, scene_boxes
    from .core.session import SESSION
    from .thumbnails import THUMBNAILS
    from .ui import legend
    from .operators import run_poller
    from . import compat
    from .core import reactions
    compat.unregister_cli_command()
    reactions.clear()
    run_poller.stop_for_unregister()
    # Put the user's scene back before the properties that describe it go away.
    preview.end_all_previews()
    keymaps.remove()
    THUMBNAILS.unregister()
    legend.unregister()
    draw.remove_handlers()
    handlers.remove()
    scene_boxes.RANKING.clear()
    scene_boxes.stop_index_poll()
    SESSION.close()
    props.unregister_properties()
    for cls in reversed(_classes()):
        bpy.utils.unregister_class(cls)
