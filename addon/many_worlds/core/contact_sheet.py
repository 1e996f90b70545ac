"""A contact sheet of worlds: each world's paths drawn from a camera into one labelled tile, over
the scene as rendered there (or a plain background), with a legend of the objects' colours.

Blender-free (numpy only) so it works headless on a farm, where there is no GPU context; the
command line renders the backgrounds.
"""
import struct
import zlib

import numpy as np

from .screen_pixels import world_to_pixels

BACKGROUND = (24, 24, 28)
LABEL = (235, 235, 235)
LABEL_BACKING = (0, 0, 0)
# 3x5 pixel glyphs, rows top to bottom, 3 bits per row; lower case is drawn as upper case.
GLYPHS = {"0": "111101101101111", "1": "010110010010111", "2": "111001111100111", "3": "111001111001111",
          "4": "101101111001001", "5": "111100111001111", "6": "111100111101111", "7": "111001001001001",
          "8": "111101111101111", "9": "111101111001111",
          "A": "010101111101101", "B": "110101110101110", "C": "011100100100011", "D": "110101101101110",
          "E": "111100110100111", "F": "111100110100100", "G": "011100101101011", "H": "101101111101101",
          "I": "111010010010111", "J": "001001001101010", "K": "101101110101101", "L": "100100100100111",
          "M": "101111111101101", "N": "110101101101101", "O": "010101101101010", "P": "110101110100100",
          "Q": "010101101110011", "R": "110101110101101", "S": "011100010001110", "T": "111010010010010",
          "U": "101101101101111", "V": "101101101101010", "W": "101101111111101", "X": "101101010101101",
          "Y": "101101010010010", "Z": "111001010100111", ".": "000000000000010", "-": "000000111000000",
          "_": "000000000000111", "#": "101111101111101", ":": "000010000010000", " ": "000000000000000"}
LEGEND_SCALE = 2


def draw_line(tile, a, b, colour):
    steps = int(max(abs(b[0] - a[0]), abs(b[1] - a[1]))) + 1
    if steps > 4 * max(tile.shape):
        return  # a segment from behind the camera: skip rather than smear
    t = np.linspace(0.0, 1.0, steps)
    xs = np.round(a[0] + (b[0] - a[0]) * t).astype(int)
    ys = np.round(a[1] + (b[1] - a[1]) * t).astype(int)
    # Two pixels wide, so thin diagonal paths stay visible in small tiles.
    for dx, dy in ((0, 0), (1, 0), (0, 1)):
        x, y = xs + dx, ys + dy
        keep = (x >= 0) & (x < tile.shape[1]) & (y >= 0) & (y < tile.shape[0])
        tile[y[keep], x[keep]] = colour


def text_width(text, scale):
    return 4 * scale * len(text) - scale


def draw_text(image, text, x, y, scale, colour=LABEL):
    """Pixel-font text with its top-left corner at (x, y); characters it lacks are left blank."""
    for k, ch in enumerate(text.upper()):
        pattern = GLYPHS.get(ch, "")
        left = x + 4 * scale * k
        for bit, on in enumerate(pattern):
            if on == "1":
                row, col = divmod(bit, 3)
                top, col_left = y + row * scale, left + col * scale
                image[top:top + scale, col_left:col_left + scale] = colour


def draw_label(tile, text, scale=3, margin=6):
    """The world's number, top-left, on a dark backing so it reads over a rendered scene."""
    tile[margin - 2:margin + 5 * scale + 2, margin - 2:margin + text_width(text, scale) + 2] = LABEL_BACKING
    draw_text(tile, text, margin, margin, scale)


def legend_rows(legend, width, scale=LEGEND_SCALE, margin=6):
    """[[(name, colour, x)]]: the legend's entries (swatch and name) in rows that fit `width`."""
    rows, row, x = [], [], margin
    for name, colour in legend:
        entry = 5 * scale + 2 * scale + text_width(name, scale) + 6 * scale
        if row and x + entry > width - margin:
            rows.append(row)
            row, x = [], margin
        row.append((name, colour, x))
        x += entry
    return rows + ([row] if row else [])


def draw_legend(width, legend, scale=LEGEND_SCALE, margin=6):
    """An image strip `width` wide: a colour swatch and the object's name per entry of `legend`
    [(name, (r, g, b) 0..255)]."""
    rows = legend_rows(legend, width, scale, margin)
    line = 5 * scale + margin
    strip = np.empty((margin + line * len(rows), width, 3), dtype=np.uint8)
    strip[:] = BACKGROUND
    for r, row in enumerate(rows):
        y = margin + r * line
        for name, colour, x in row:
            strip[y:y + 5 * scale, x:x + 5 * scale] = colour
            draw_text(strip, name, x + 7 * scale, y, scale)
    return strip


def render(tiles, view, projection, view_size, tile_width=320, columns=None, backgrounds=None, legend=()):
    """A contact sheet: RGB image (rows, cols, 3) uint8.

    tiles: [(world, [(polyline (points, 3), (r, g, b) 0..255)])], one per world; backgrounds: an
    image (tile height, tile width, 3) uint8 per tile to draw the paths over (the rendered scene),
    or None for a plain background; legend: [(object name, (r, g, b))] drawn in a strip below.
    """
    tile_height = tile_size(tile_width, view_size)[1]
    columns = columns or int(np.ceil(np.sqrt(len(tiles))))
    rows = int(np.ceil(len(tiles) / columns))
    sheet = np.zeros((rows * (tile_height + 2), columns * (tile_width + 2), 3), dtype=np.uint8)
    sheet[:] = 60
    perspective = np.asarray(projection) @ np.asarray(view)
    for k, (world, polylines) in enumerate(tiles):
        tile = np.zeros((tile_height, tile_width, 3), dtype=np.uint8)
        tile[:] = BACKGROUND if backgrounds is None else backgrounds[k]
        for polyline, colour in polylines:
            # Image rows count down from the top.
            x, y, visible = world_to_pixels(polyline, perspective, (tile_width, tile_height), y_down=True)
            pixels = np.stack([x, y], axis=-1)
            for i in range(len(pixels) - 1):
                if visible[i] and visible[i + 1]:
                    draw_line(tile, pixels[i], pixels[i + 1], colour)
        draw_label(tile, str(world))
        r, c = divmod(k, columns)
        y, x = r * (tile_height + 2) + 1, c * (tile_width + 2) + 1
        sheet[y:y + tile_height, x:x + tile_width] = tile
    if legend:
        sheet = np.concatenate([sheet, draw_legend(sheet.shape[1], legend)])
    return sheet


def tile_size(tile_width, view_size):
    """(width, height) of a tile showing a view of `view_size` pixels."""
    return tile_width, max(1, int(round(tile_width * view_size[1] / view_size[0])))


def save_png(image, path):
    """Writes an RGB uint8 image as PNG (zlib only, no imaging library needed)."""
    height, width, _ = image.shape
    raw = b"".join(b"\x00" + image[y].tobytes() for y in range(height))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))
