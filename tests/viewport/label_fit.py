"""Measuring the text a panel draws against the width Blender gives it.

A panel's draw (and the draw_item of the lists it shows) is run on a recording layout: every call
goes to the real layout, so the screen shows the real panel, and every label, property and
operator is also kept with the layout it was put in (column, row, split, box, list). Once drawn,
each item gets its share of the panel's width as Blender's layout engine shares it out (a row
squeezes its items in proportion to their natural widths when they do not fit; a split gives
its first part `factor`), and its text is measured with blf at the UI scale. An item whose text
needs more than its share is cut on screen ("Perturb…", "Widt 2.00").

Pixels are at UI scale 1 (one UI unit is 20 px) and scale with it.
"""
import math

import blf
import bpy

UNIT = 20
FONT_POINTS = 11
# The sidebar's category tabs; inside the region, a panel's box and its content's inset on each
# side; a box's inset inside a panel.
TABS = 21
PANEL_INSET = 10 + 7
BOX_INSET = 6
# Beside a list's rows: the scrollbar and the row's own margins.
LIST_INSET = 20
# What an item needs besides its text to show it whole (margins, icon, check box, menu arrow),
# in UI units. Labels are drawn with a small margin; buttons and fields keep one on both sides.
LABEL_PAD = 0.4
BUTTON_PAD = 0.8
FIELD_GAP = 1.0
ICON = 1.35
BUTTON_ICON = 1.15
CHECKBOX = 1.0
MENU_ARROW = 0.9


def text_px(text, scale):
    blf.size(0, FONT_POINTS * scale)
    return blf.dimensions(0, text)[0]


class Item:
    """Text put in a layout: what it shows, how much more it needs, whether it has a fixed width."""

    def __init__(self, kind, text, pad_units, fixed=False, where=""):
        self.kind, self.text, self.pad_units, self.fixed, self.where = kind, text, pad_units, fixed, where

    def needed(self, scale):
        return (text_px(self.text, scale) if self.text else 0) + self.pad_units * UNIT * scale

    def natural(self, scale):
        if self.fixed:
            return UNIT * scale
        return self.needed(scale) + 0.6 * UNIT * scale


class Recording:
    """A UILayout stand-in that records what is put in it; everything else goes to the real one."""

    def __init__(self, layout, kind="column", factor=0.0, where=""):
        object.__setattr__(self, "_layout", layout)
        object.__setattr__(self, "_kind", kind)
        object.__setattr__(self, "_factor", factor)
        object.__setattr__(self, "_slots", [])
        object.__setattr__(self, "_where", where)

    def __getattr__(self, name):
        return getattr(self._layout, name)

    def __setattr__(self, name, value):
        setattr(self._layout, name, value)

    # --- sub-layouts ---

    def _child(self, layout, kind, factor=0.0):
        child = Recording(layout, kind, factor, self._where)
        self._slots.append(child)
        return child

    def row(self, **kw):
        return self._child(self._layout.row(**kw), "row")

    def column(self, **kw):
        return self._child(self._layout.column(**kw), "column")

    def box(self):
        return self._child(self._layout.box(), "box")

    def split(self, factor=0.0, **kw):
        return self._child(self._layout.split(factor=factor, **kw), "split", factor)

    def column_flow(self, **kw):
        return self._child(self._layout.column_flow(**kw), "column")

    def grid_flow(self, **kw):
        return self._child(self._layout.grid_flow(**kw), "column")

    def template_list(self, *args, **kw):
        rows = self._child(self._layout, "list")
        global _LIST
        outer, _LIST = _LIST, rows
        try:
            # Blender draws the visible rows (draw_item) during this call.
            self._layout.template_list(*args, **kw)
        finally:
            _LIST = outer

    # --- items ---

    def _add(self, kind, text, pad, fixed=False):
        self._slots.append(Item(kind, text, pad, fixed, self._where))

    def label(self, text="", icon="NONE", **kw):
        self._layout.label(text=text, icon=icon, **kw)
        icon_units = ICON if (icon != "NONE" or kw.get("icon_value")) else 0
        self._add("label", text, LABEL_PAD + icon_units, fixed=not text)

    def operator(self, idname, text=None, icon="NONE", **kw):
        if text is None:
            category, name = idname.split(".")
            text = getattr(getattr(bpy.ops, category), name).get_rna_type().name
        props = self._layout.operator(idname, text=text, icon=icon, **kw)
        icon_units = BUTTON_ICON if icon != "NONE" else 0
        self._add("operator", text, BUTTON_PAD + icon_units, fixed=not text)
        return props

    def prop(self, data, name, text=None, icon="NONE", **kw):
        self._layout.prop(data, name, text=text, icon=icon, **kw) if text is not None else \
            self._layout.prop(data, name, icon=icon, **kw)
        for kind, shown, pad, fixed in prop_items(data, name, text, icon, kw):
            self._add(kind, shown, pad, fixed)

    # --- widths ---

    def items_with_width(self, width, scale, out):
        """(item, width it gets) for every item under this layout, given this layout's width."""
        if self._kind == "box":
            width -= 2 * BOX_INSET * scale
        if self._kind == "list":
            width -= LIST_INSET * scale
        if self._kind == "row":
            shares = _row_shares(self._slots, width, scale)
        elif self._kind == "split":
            first = width * self._factor if self._factor > 0 else width / max(1, len(self._slots))
            rest = (width - first) / max(1, len(self._slots) - 1)
            shares = [first] + [rest] * (len(self._slots) - 1)
        else:
            shares = [width] * len(self._slots)
        for slot, share in zip(self._slots, shares):
            if isinstance(slot, Recording):
                slot.items_with_width(share, scale, out)
            else:
                out.append((slot, share))
        return out

    def natural(self, scale):
        widths = [s.natural(scale) for s in self._slots]
        if not widths:
            return 0
        return sum(widths) if self._kind in ("row", "split") else max(widths)


def _row_shares(slots, width, scale):
    """A row's width shared out: fixed items (icon only) keep one unit, the others their natural
    width, all scaled down alike when they do not fit."""
    fixed = sum(UNIT * scale for s in slots if isinstance(s, Item) and s.fixed)
    naturals = [0 if isinstance(s, Item) and s.fixed else s.natural(scale) for s in slots]
    total = sum(naturals)
    factor = max(1.0, total / max(1.0, width - fixed)) if total else 1.0
    return [UNIT * scale if isinstance(s, Item) and s.fixed else n / factor if total > width - fixed
            else n + (width - fixed - total) / max(1, len(naturals)) for s, n in zip(slots, naturals)]


_LIST = None


def _value_text(data, name, prop, index=None):
    """A number as its field shows it: the scene's units for lengths, angles, times and speeds."""
    value = getattr(data, name)
    if index is not None:
        value = value[index]
    if prop.type == "INT":
        return str(value)
    units = bpy.context.scene.unit_settings
    category = {"LENGTH": "LENGTH", "ROTATION": "ROTATION", "TIME_ABSOLUTE": "TIME_ABSOLUTE",
                "VELOCITY": "VELOCITY"}.get(prop.unit)
    if category and units.system != "NONE":
        try:
            return bpy.utils.units.to_string(units.system, category, value, precision=prop.precision)
        except (ValueError, TypeError):
            pass
    return f"{value:.{max(prop.precision, 0)}f}"


def prop_items(data, name, text, icon, kw):
    """What layout.prop(data, name) shows: (kind, text, pad units, fixed width) per field."""
    prop = data.bl_rna.properties[name]
    label = prop.name if text is None else text
    icon_units = ICON if icon != "NONE" else 0
    if prop.type == "BOOLEAN":
        if kw.get("toggle") or icon != "NONE" and not label:
            return [("toggle", label, BUTTON_PAD + icon_units, not label)]
        return [("checkbox", label, LABEL_PAD + CHECKBOX, not label)]
    if prop.type == "ENUM":
        items = {item.identifier: item.name for item in prop.enum_items}
        if kw.get("expand"):
            return [("enum", items[i], BUTTON_PAD, False) for i in items]
        if kw.get("icon_only"):
            return [("enum", "", BUTTON_PAD, True)]
        shown = items.get(getattr(data, name), "")
        return [("enum", f"{label}  {shown}" if label else shown, BUTTON_PAD + MENU_ARROW + icon_units, False)]
    if prop.type in ("INT", "FLOAT"):
        if getattr(prop, "is_array", False) and prop.array_length > 1:
            axes = "XYZW"
            return [("number", f"{axes[k] if not label else axes[k]} {_value_text(data, name, prop, k)}",
                     BUTTON_PAD + FIELD_GAP, False) for k in range(prop.array_length)]
        shown = _value_text(data, name, prop)
        return [("number", f"{label} {shown}" if label else shown, BUTTON_PAD + FIELD_GAP, False)]
    # Strings are input fields: their content scrolls rather than being a label.
    return []


def record_list_row(layout, where):
    """The recording layout a list's draw_item draws into, as a row of the list being drawn."""
    rec = Recording(layout, "column", where=where)
    if _LIST is not None:
        _LIST._slots.append(rec)
    return rec


def panel_width(region, scale, has_tabs):
    """The width a panel's layout has in a sidebar region: the region less the tabs, the panel's
    rounded box and its inset on both sides."""
    tabs = math.ceil(TABS * scale) if has_tabs else 0
    return region.width - tabs - 2 * PANEL_INSET * scale


def cut_items(recordings, width, scale):
    """[(where, text, needed px, available px)] of every recorded item whose text does not fit."""
    out = []
    for rec in recordings:
        for item, share in rec.items_with_width(width, scale, []):
            if item.text and item.needed(scale) > share + 0.5:
                out.append((item.where, item.text, round(item.needed(scale)), round(share)))
    return out


def widest(recordings, width, scale):
    """(where, text, needed px, available px) of the item with the least room to spare."""
    best = None
    for rec in recordings:
        for item, share in rec.items_with_width(width, scale, []):
            if item.text and (best is None or share - item.needed(scale) < best[3] - best[2]):
                best = (item.where, item.text, round(item.needed(scale)), round(share))
    return best
