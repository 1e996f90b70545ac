"""Every difference between Blender 3.4 and 4.2+ that the add-on meets, in one place."""
import importlib

import bpy
import gpu

IS_4 = bpy.app.version >= (4, 0, 0)

# Blender 3.4 accepts both spellings; 4.x only the short ones. Resolved once at import.
_SHADER_NAMES = {"UNIFORM_COLOR": "3D_UNIFORM_COLOR", "POLYLINE_UNIFORM_COLOR": "3D_POLYLINE_UNIFORM_COLOR",
                 "POLYLINE_FLAT_COLOR": "3D_POLYLINE_FLAT_COLOR"}


def builtin_shader(name):
    """A gpu builtin shader by its 4.x name."""
    try:
        return gpu.shader.from_builtin(name)
    except ValueError:
        return gpu.shader.from_builtin(_SHADER_NAMES[name])


def temp_override(context, **kwargs):
    """Context override for operators (Blender >= 3.2 has temp_override; the dict form is gone in 4)."""
    return context.temp_override(**kwargs)


def new_fcurve(action, data_path, index, group):
    """An F-curve on an action. Blender 4.4+ layers actions into slots, but `Action.fcurves`
    still addresses the legacy single-slot view used by objects with one action."""
    return action.fcurves.new(data_path, index=index, action_group=group)


def find_fcurve(action, data_path, index):
    return action.fcurves.find(data_path, index=index)


# `blender -c many_worlds COMMAND ...` (4.2+). Blender looks commands up before it reads `--addons`,
# so the command exists when the add-on is enabled in the preferences (as an installed extension).
CLI_COMMAND = "many_worlds"
_cli_handles = []


def register_cli_command(package):
    """Forward `blender -c many_worlds ARGS` to `<package>.cli.main(ARGS)`; nothing before 4.2."""
    if not hasattr(bpy.utils, "register_cli_command"):
        return

    def execute(argv):
        # Imported on use: the command line module is not needed to register the add-on.
        return importlib.import_module(".cli", package).main(list(argv))

    _cli_handles.append(bpy.utils.register_cli_command(CLI_COMMAND, execute))


def unregister_cli_command():
    while _cli_handles:
        bpy.utils.unregister_cli_command(_cli_handles.pop())
