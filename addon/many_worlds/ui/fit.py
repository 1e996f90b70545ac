"""Text that fits the sidebar: the width of UI text as Blender draws it, and long messages wrapped
into labels that are never cut."""
import blf

FONT_ID = 0
# Blender's widget text at UI scale 1 (User Interface style "Widget", 11 points at 72 dpi).
UI_FONT_POINTS = 11
# Pixels at UI scale 1 that a label's text does not get of the sidebar's width: the category tabs,
# the panel's box and inset on both sides, a box inside the panel, the icon and its gap, the margin.
SIDEBAR_TABS = 21
PANEL_MARGINS = 2 * (10 + 7) + 2 * 6
ICON_WIDTH = 27 + 4
# A popup drawn from a panel is at most this wide at UI scale 1.
POPUP_WIDTH = 230


def text_width(text, scale):
    """Width in pixels of `text` in the UI font at UI scale `scale`."""
    blf.size(FONT_ID, UI_FONT_POINTS * scale)
    return blf.dimensions(FONT_ID, text)[0]


def label_width(context):
    """Pixels a label's text has in a panel of the current region (after margins and its icon)."""
    scale = context.preferences.view.ui_scale
    region_px = min(context.region.width, POPUP_WIDTH * scale) if context.region else POPUP_WIDTH * scale
    return region_px - (SIDEBAR_TABS + PANEL_MARGINS + ICON_WIDTH) * scale


# Joins words that must share a line, such as a value and its unit.
NO_BREAK_SPACE = "\u00a0"


def wrap(text, width_px, scale):
    """Lines of `text`, broken at spaces (never at NO_BREAK_SPACE), each at most `width_px` wide
    (a word longer than that is broken inside)."""
    lines, line = [], ""
    for word in (w for w in text.split(" ") if w):
        candidate = f"{line} {word}" if line else word
        if text_width(candidate, scale) <= width_px:
            line = candidate
            continue
        if line:
            lines.append(line)
        while text_width(word, scale) > width_px and len(word) > 1:
            cut = max(1, next(k for k in range(len(word), 0, -1) if text_width(word[:k], scale) <= width_px))
            lines.append(word[:cut])
            word = word[cut:]
        line = word
    return lines + [line] if line or not lines else lines


def wrapped_labels(layout, context, text, icon="NONE"):
    """A long message as labels that fit the region's width (Blender cuts a label, never wraps it)."""
    scale = context.preferences.view.ui_scale
    column = layout.column(align=True)
    for k, line in enumerate(wrap(text, label_width(context), scale)):
        column.label(text=line, icon=icon if k == 0 else "BLANK1")
