"""What the viewport tests of the sidebar share: every panel and list of the add-on drawn through a
recording layout (label_fit), each text measured against the width its panel gives it, full-window
screenshots, and the sidebar brought to the Many Worlds tab and scrolled as a user would.

The output folder is the one the test script was given (run.sh passes it after "--")."""
import os
import sys

import bpy

import label_fit
import viewport_helpers
from many_worlds.ui import lists, panels

OUT_DIR = sys.argv[sys.argv.index("--") + 1]

# Per drawn panel: (panel label, its recording layout, the region it drew in).
DRAWN = []


class PanelProxy:
    """The panel as its draw sees it, with the recording layout in place of the real one."""

    def __init__(self, panel, layout):
        object.__setattr__(self, "_panel", panel)
        object.__setattr__(self, "layout", layout)

    def __getattr__(self, name):
        return getattr(self._panel, name)


def recording_draw(draw, label):
    # Blender passes a Python draw function as many arguments as it names: name them exactly.
    def recorded(self, context):
        rec = label_fit.Recording(self.layout, where=label)
        DRAWN.append((label, rec, context.region))
        draw(PanelProxy(self, rec), context)
    return recorded


def recording_draw_item(draw_item, where):
    def recorded(self, context, layout, data, item, icon, active_data, active_propname, index=0, flt_flag=0):
        rec = label_fit.record_list_row(layout, where)
        if draw_item.__code__.co_argcount >= 10:
            draw_item(self, context, rec, data, item, icon, active_data, active_propname, index, flt_flag)
        else:
            draw_item(self, context, rec, data, item, icon, active_data, active_propname, index)
    return recorded


def record_panels():
    """Make every panel and list of the add-on draw through a recording layout."""
    for cls in panels.classes:
        cls.draw = recording_draw(cls.draw, cls.bl_label)
    for cls in lists.classes:
        cls.draw_item = recording_draw_item(cls.draw_item, cls.__name__)


def open_expert_panels():
    """Show the collapsed subpanels open, as after a click on their header: each is registered again
    under a new id without DEFAULT_CLOSED (the sidebar keeps a panel's closed state by its id)."""
    for cls in panels.classes:
        if "DEFAULT_CLOSED" in getattr(cls, "bl_options", set()):
            bpy.utils.unregister_class(cls)
            opened = type(cls.__name__ + "_open", (cls,), {"bl_idname": cls.bl_idname + "_open",
                                                          "bl_options": set(cls.bl_options) - {"DEFAULT_CLOSED"}})
            bpy.utils.register_class(opened)


def redraw_all():
    """Draw every window now, recording what the panels draw."""
    DRAWN.clear()
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        area.tag_redraw()
    with bpy.context.temp_override(window=window):
        bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=1)


def window_screenshot(name):
    """The whole window as the user sees it (saved as `name`), as RGB rows from the bottom."""
    return viewport_helpers.window_screenshot(OUT_DIR, name, redraw_all)


def save_rgb(rgb, name):
    viewport_helpers.save_rgb(rgb, os.path.join(OUT_DIR, name))


def crop(rgb, out_name, region):
    """Save the part of a window screenshot that a region covers; returns its RGB pixels."""
    part = rgb[region.y:region.y + region.height, region.x:region.x + region.width]
    save_rgb(part, out_name)
    return part


def has_tabs(region):
    """The sidebar shows category tabs (and gives them width) when panels of several categories poll."""
    return region.type == "UI"


def measure(state):
    """Cut texts and the tightest text of the panels drawn in the last redraw."""
    scale = bpy.context.preferences.view.ui_scale
    cut, tightest, drawn, items = [], None, [], []
    for label, rec, region in DRAWN:
        width = label_fit.panel_width(region, scale, has_tabs(region))
        drawn.append(label)
        items += [(item.where, item.kind, item.text, round(item.needed(scale)), round(share))
                  for item, share in rec.items_with_width(width, scale, []) if item.text]
        # The header: its label after the collapse arrow, left of the drag handle.
        header = label_fit.Recording(None, where=f"{label} (header)")
        header._add("label", label, 2 * label_fit.ICON)
        cut += label_fit.cut_items([rec, header], width, scale)
        best = label_fit.widest([rec, header], width, scale)
        if best and (tightest is None or best[3] - best[2] < tightest[3] - tightest[2]):
            tightest = best
    return {"state": state, "drawn": list(dict.fromkeys(drawn)), "cut": cut, "tightest": tightest,
            "items": list(dict.fromkeys(items))}


def texts(where):
    return [item.text for label, rec, region in DRAWN if label == where
            for item, _ in rec.items_with_width(1000, 1.0, [])]


def show_many_worlds_tab(window, area):
    """Switch the sidebar to the Many Worlds tab (a generator: the events are handled between
    steps). Blender 4 lets a script set it; on 3.4, Ctrl+Wheel over the tabs steps through them
    as a user would."""
    sidebar = next(r for r in area.regions if r.type == "UI")
    if hasattr(sidebar, "active_panel_category"):
        sidebar.active_panel_category = "Many Worlds"
        return
    # Over the tabs, at the sidebar's right edge.
    x, y = sidebar.x + sidebar.width - 8, sidebar.y + sidebar.height // 2
    window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
    yield
    for _ in range(8):
        redraw_all()
        if any(label == "Sample" for label, _, _ in DRAWN):
            return
        window.event_simulate(type="WHEELDOWNMOUSE", value="PRESS", x=x, y=y, ctrl=True)
        yield
    raise AssertionError("the sidebar never showed the Many Worlds tab")


def scroll(window, area, region_type="WINDOW", down=True, steps=30):
    """Scroll a region of an editor towards its end (a generator), a mouse wheel's step at a time:
    the variation panel at the end of the Rigid Body settings, or the lower panels of the sidebar.
    The region's own scroll operator, which the wheel runs, so that a list under the mouse does
    not take the steps instead."""
    region = next(r for r in area.regions if r.type == region_type)
    with bpy.context.temp_override(window=window, area=area, region=region):
        for _ in range(steps):
            (bpy.ops.view2d.scroll_down if down else bpy.ops.view2d.scroll_up)()
    yield
