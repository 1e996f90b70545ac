"""Path colours and the contact sheet's pixels, without Blender: objects can be told apart, and
the sheet's legend names them in their colours."""
import numpy as np

from many_worlds.core import contact_sheet, palette

SELECTED_CYAN = (0.1, 0.85, 1.0)


def distance(a, b):
    return float(np.max(np.abs(np.subtract(a[:3], b[:3]))))


def lab(colour):
    """CIELAB (D65) of a display-space (sRGB) colour."""
    rgb = np.array(colour[:3], dtype=float)
    linear = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    xyz = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]) @ linear
    xyz /= np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 0.008856, np.cbrt(xyz), 7.787 * xyz + 16 / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e(a, b):
    return float(np.linalg.norm(lab(a) - lab(b)))


def test_twenty_objects_get_twenty_colours_far_apart_and_far_from_the_selected_worlds_cyan():
    names = [f"Cube.{k:03d}" for k in range(20)]
    colours = list(palette.object_colours(names, simulated=range(20)).values())
    assert len(set(colours)) == 20
    assert min(delta_e(a, b) for i, a in enumerate(colours) for b in colours[i + 1:]) >= 19
    assert min(delta_e(c, SELECTED_CYAN) for c in colours) >= 35
    # Readable on the viewport's grey.
    assert min(delta_e(c, (0.24, 0.24, 0.24)) for c in colours) >= 40


def test_objects_keep_one_colour_simulated_first_and_updated_bodies_share_theirs():
    names = ["Ground", "Ball", "Cube", "Ball"]          # body 3 is Ball updated after sampling
    colours = palette.body_colours(names, simulated=[1, 2, 3])
    assert colours[1] == palette.PALETTE[0] and colours[2] == palette.PALETTE[1]
    assert colours[3] == colours[1] and colours[0] == palette.PALETTE[2]


def test_a_rejected_world_is_faint_and_greyer_but_keeps_a_hint_of_its_hue():
    for colour in palette.PALETTE:
        faded = palette.rejected(colour)
        assert faded[3] < 0.2 * palette.matching(colour)[3]
        assert 0 < np.ptp(faded[:3]) < 0.5 * np.ptp(colour)


def test_the_sheet_draws_each_path_in_its_colour_over_the_background_and_a_legend_below():
    view, projection = np.eye(4), np.eye(4)
    line = np.array([[-0.5, 0.0, 0.5], [0.5, 0.0, 0.5]])   # across the middle of the view
    backdrop = np.full((50, 100, 3), 120, dtype=np.uint8)
    red, green = (200, 30, 30), (30, 200, 30)
    sheet = contact_sheet.render([(7, [(line, red)]), (8, [(line + [0, 0.4, 0], green)])], view, projection,
                                 (100, 50), tile_width=100, columns=2, backgrounds=[backdrop, backdrop],
                                 legend=[("Marble", red), ("Die", green)])
    tiles, legend = sheet[:52], sheet[52:]
    left, right = tiles[1:51, 1:101], tiles[1:51, 103:203]
    assert (left == red).all(axis=-1).sum() > 100 and not (left == green).all(axis=-1).any()
    assert (right == green).all(axis=-1).sum() > 100
    # Away from the paths and the world's number, the backdrop shows.
    assert (left[40:] == 120).all()
    # The legend: a swatch per object, and text (light pixels) beside each.
    assert (legend == red).all(axis=-1).sum() >= 100 and (legend == green).all(axis=-1).sum() >= 100
    assert (legend == contact_sheet.LABEL).all(axis=-1).sum() > 50
