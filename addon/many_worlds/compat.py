"""Every difference between the Blender versions the add-on supports (3.4 to 5.2) that it meets,
in one place."""
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


# A path property that takes "//" (relative to the .blend) must say so from 5.0 on, or setting one
# warns; 3.4 does not know the option.
BLEND_RELATIVE_PATH = ({"PATH_SUPPORTS_BLEND_RELATIVE"}
                       if "is_path_supports_blend_relative" in bpy.types.Property.bl_rna.properties else set())


def temp_override(context, **kwargs):
    """Context override for operators (Blender >= 3.2 has temp_override; the dict form is gone in 4)."""
    return context.temp_override(**kwargs)


# --- animation ------------------------------------------------------------------------------
# Blender 4.4 made every action slotted: an object plays the F-curves of its own slot
# (animation_data.action_slot), kept in a channelbag on a strip of a layer. 5.0 removed the legacy
# view (Action.fcurves, .groups, .id_root). 3.4 to 4.3 have the legacy API only. Every read and
# write of an object's keys goes through the functions below, which take the object, not the
# action, so no caller needs to know which API it runs on.
SLOTTED_ACTIONS = bpy.app.version >= (4, 4, 0)


def _slot_of(ob):
    """The object's action slot (4.4+), or None when it has none assigned."""
    return ob.animation_data.action_slot


def _channelbag(action, slot, ensure=False):
    """The channelbag of slot on the action's first keyframe strip; made when ensure is set."""
    for layer in action.layers:
        for strip in layer.strips:
            if strip.type == "KEYFRAME":
                bag = strip.channelbag(slot, ensure=ensure)
                if bag is not None:
                    return bag
    if not ensure:
        return None
    layer = action.layers[0] if len(action.layers) else action.layers.new("Layer")
    strip = layer.strips[0] if len(layer.strips) else layer.strips.new(type="KEYFRAME")
    return strip.channelbag(slot, ensure=True)


def _action(ob):
    data = ob.animation_data
    return data.action if data is not None else None


def _fcurve_collection(action, slot):
    """The collection holding the F-curves that action plays through slot (None: there is none)."""
    if not SLOTTED_ACTIONS:
        return action.fcurves
    bag = _channelbag(action, slot) if slot is not None else None
    return bag.fcurves if bag is not None else None


def _object_fcurve_collection(ob):
    action = _action(ob)
    if action is None:
        return None
    return _fcurve_collection(action, _slot_of(ob) if SLOTTED_ACTIONS else None)


def object_fcurves(ob):
    """The F-curves that animate ob through its action (empty when it has none)."""
    fcurves = _object_fcurve_collection(ob)
    return list(fcurves) if fcurves is not None else []


def find_fcurve(ob, data_path, index=0):
    """ob's F-curve of data_path[index], or None."""
    fcurves = _object_fcurve_collection(ob)
    return fcurves.find(data_path, index=index) if fcurves is not None else None


def ensure_action(ob, name):
    """ob's action, made (named name) when it has none; on 4.4+ with a slot of ob assigned."""
    if ob.animation_data is None:
        ob.animation_data_create()
    data = ob.animation_data
    if data.action is None:
        data.action = bpy.data.actions.new(name)
    if SLOTTED_ACTIONS and data.action_slot is None:
        action = data.action
        # A slot made for this object before (its name is the object's, prefixed "OB") is reused.
        slot = next((s for s in action.slots if s.target_id_type in {"OBJECT", "UNSPECIFIED"}
                     and s.name_display == ob.name), None)
        data.action_slot = slot or action.slots.new(id_type="OBJECT", name=ob.name)
    return data.action


def new_fcurve(ob, data_path, index, group):
    """A new, empty F-curve of data_path[index] for ob (which has an action: ensure_action), in
    group, replacing the one there was. The object's other F-curves stay as they are."""
    action = _action(ob)
    bag = _channelbag(action, _slot_of(ob), ensure=True) if SLOTTED_ACTIONS else None
    fcurves = bag.fcurves if bag is not None else action.fcurves
    old = fcurves.find(data_path, index=index)
    if old is not None:
        fcurves.remove(old)
    if bag is None:
        return fcurves.new(data_path, index=index, action_group=group)
    fcurve = fcurves.new(data_path, index=index)
    fcurve.group = bag.groups.get(group) or bag.groups.new(group)
    return fcurve


def remove_fcurve(ob, fcurve):
    _object_fcurve_collection(ob).remove(fcurve)


class AnimationUsers:
    """Which objects play the same keys (the same action, and on 4.4+ the same slot), found in one
    pass over the file's objects, so that asking it of every object of a big scene stays linear."""

    def __init__(self, objects):
        self._users = {}
        for ob in objects:
            key = self._key(ob)
            if key is not None:
                self._users.setdefault(key, []).append(ob)

    @staticmethod
    def _key(ob):
        action = _action(ob)
        if action is None:
            return None
        slot = _slot_of(ob) if SLOTTED_ACTIONS else None
        return action.as_pointer(), slot.as_pointer() if slot is not None else 0

    def others(self, ob):
        """The other objects that play ob's keys."""
        return [other for other in self._users.get(self._key(ob), []) if other != ob]

    def leave(self, ob):
        """ob plays keys of its own from now on (its action was copied)."""
        users = self._users.get(self._key(ob), [])
        if ob in users:
            users.remove(ob)


def other_animation_of(ob, data_path):
    """What else than ob's own action sets data_path: 'a driver', 'the NLA' or None. The add-on
    reads only the keys of the object's active action."""
    data = ob.animation_data
    if data is None:
        return None
    if any(d.data_path == data_path for d in data.drivers):
        return "a driver"
    for track in data.nla_tracks:
        for strip in track.strips:
            if track.mute or strip.mute or strip.action is None:
                continue
            slot = strip.action_slot if SLOTTED_ACTIONS else None
            fcurves = _fcurve_collection(strip.action, slot)
            if fcurves is not None and any(f.data_path == data_path for f in fcurves):
                return "the NLA"
    return None


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
