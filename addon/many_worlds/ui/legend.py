"""The legend of the path colours in the panel: each drawn object's name beside a swatch of its
colour (a panel cannot draw a colour by itself; a preview icon made of one colour can), two to a
row, and how the worlds the boxes reject look."""
import bpy
import bpy.utils.previews

from ..core import palette
from ..core.session import SESSION
from ..draw import paths
from . import fit

SWATCH_PIXELS = 16
VIEWPORT_GREY = (0.24, 0.24, 0.24)
_SWATCHES = []   # one bpy.utils.previews collection while the add-on is registered


def swatch_icon(colour):
    """icon_id of a square of `colour` ((r, g, b) or (r, g, b, a) in display space), made once."""
    if not _SWATCHES:
        _SWATCHES.append(bpy.utils.previews.new())
    swatches = _SWATCHES[0]
    rgba = list(colour[:3]) + [colour[3] if len(colour) > 3 else 1.0]
    key = "%.3f %.3f %.3f %.3f" % tuple(rgba)
    if key not in swatches:
        icon = swatches.new(key)
        icon.icon_size = (SWATCH_PIXELS, SWATCH_PIXELS)
        icon.icon_pixels_float = rgba * SWATCH_PIXELS ** 2
    return swatches[key].icon_id


def legend_entries(context):
    """[(object name, (r, g, b))] of the objects whose paths are drawn, in colour order."""
    view = SESSION.view
    if view is None:
        return []
    drawn = {view.body_names[b] for b in paths.chosen_bodies(context, view)}
    colours = palette.object_colours(view.body_names, view.simulated_bodies())
    return [(name, colour) for name, colour in colours.items() if name in drawn]


def legend_columns(names, label_px, scale):
    """Two columns when every name fits half the width a label has, else one."""
    half = (label_px - fit.ICON_WIDTH * scale) / 2
    return 2 if all(fit.text_width(name, scale) <= half for name in names) else 1


def draw_legend(layout, context):
    """The colour of each drawn object's paths, and the look of worlds the boxes reject."""
    entries = legend_entries(context)
    if not entries or not context.scene.mwb.show_paths:
        return
    scale = context.preferences.view.ui_scale
    label_px = fit.label_width(context)
    columns = legend_columns([name for name, _ in entries], label_px, scale)
    flow = layout.grid_flow(row_major=True, columns=columns, even_columns=True, align=True)
    for name, colour in entries:
        flow.label(text=name, icon_value=swatch_icon(colour))
    objects = len(palette.object_order(SESSION.view.body_names, SESSION.view.simulated_bodies()))
    if objects > len(palette.PALETTE):
        fit.wrapped_labels(layout, context, f"{objects} objects: colours repeat after the first "
                                            f"{len(palette.PALETTE)}", "INFO")
    if SESSION.view is not None and not SESSION.view.matching.all():
        # As a rejected path looks over the viewport's grey.
        faded = palette.over(palette.rejected(entries[0][1]), VIEWPORT_GREY)
        layout.label(text="Faint grey: rejected", icon_value=swatch_icon(faded))


def unregister():
    while _SWATCHES:
        bpy.utils.previews.remove(_SWATCHES.pop())
