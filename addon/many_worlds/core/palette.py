"""Colours of the objects' paths, shared by the viewport overlay, the panel's legend and the
command line's contact sheet (bpy-free).

Each object keeps one colour in every world: the simulated objects take the palette in the order
of the library's bodies, then any other object (a body updated after sampling has several body
indices but one object name, so one colour). Cyan is left out of the palette: it marks the
selected world.
"""

# Readable on Blender's grey viewport and on rendered scenes; display-space RGB in [0, 1]. Twenty
# colours, every two at least 19 apart in CIELAB (ΔE76) and at least 36 from the selected world's
# cyan, so that up to 20 objects never share one; beyond that they repeat, and the legend says so.
PALETTE = (
    (1.00, 0.45, 0.05),   # orange
    (1.00, 0.85, 0.10),   # yellow
    (0.35, 0.85, 0.25),   # green
    (1.00, 0.30, 0.70),   # pink
    (0.62, 0.45, 1.00),   # violet
    (0.90, 0.15, 0.15),   # red
    (0.25, 0.45, 1.00),   # blue
    (0.85, 0.70, 0.50),   # tan
    (0.75, 0.94, 0.27),   # lime
    (0.57, 0.12, 0.71),   # purple
    (0.27, 0.60, 0.56),   # teal
    (0.60, 0.39, 0.14),   # brown
    (0.86, 0.75, 1.00),   # lavender
    (0.10, 0.50, 0.10),   # dark green
    (0.94, 0.20, 0.90),   # magenta
    (0.50, 0.50, 0.00),   # olive
    (0.75, 0.35, 0.45),   # rose
    (0.35, 0.20, 0.75),   # indigo
    (0.67, 1.00, 0.76),   # mint
    (0.98, 0.75, 0.83),   # light pink
)
MATCHING_ALPHA = 0.9
# A world the boxes reject: its object's colour faded towards grey and mostly transparent, so
# matched and rejected worlds stay apart while the object can still be told.
REJECTED_GREY = 0.55
REJECTED_MIX = 0.65
REJECTED_ALPHA = 0.14


def object_order(body_names, simulated):
    """Object names in colour order: those of the simulated bodies first (library order), then
    the others. simulated: body indices the simulation moves."""
    simulated = set(simulated)
    first = [name for i, name in enumerate(body_names) if i in simulated]
    return list(dict.fromkeys(first + list(body_names)))


def object_colours(body_names, simulated):
    """{object name: (r, g, b)} for every object of the library."""
    return {name: PALETTE[k % len(PALETTE)] for k, name in enumerate(object_order(body_names, simulated))}


def body_colours(body_names, simulated):
    """(r, g, b) per body index: the colour of the object the body stands for."""
    colours = object_colours(body_names, simulated)
    return [colours[name] for name in body_names]


def matching(colour):
    return tuple(colour[:3]) + (MATCHING_ALPHA,)


def rejected(colour):
    grey = [c + (REJECTED_GREY - c) * REJECTED_MIX for c in colour[:3]]
    return tuple(grey) + (REJECTED_ALPHA,)


def over(colour, background):
    """(r, g, b): an (r, g, b, a) colour blended over an opaque background."""
    a = colour[3]
    return tuple(c * a + b * (1 - a) for c, b in zip(colour[:3], background))


def to_bytes(colour):
    """(r, g, b) in [0, 1] -> 0..255 ints, for images."""
    return tuple(int(round(255 * max(0.0, min(1.0, c)))) for c in colour[:3])
