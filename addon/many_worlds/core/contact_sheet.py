"""A contact sheet of worlds: each world's paths drawn from a camera into one labelled tile.

Blender-free (numpy only) so it works headless on a farm, where there is no GPU context.
"""
import struct
import zlib

import numpy as np

BACKGROUND = (24, 24, 28)
PATH_COLOURS = [(255, 180, 40), (80, 200, 255), (140, 255, 120), (255, 110, 150), (200, 160, 255), (255, 255, 140)]
LABEL = (235, 235, 235)
# 3x5 pixel digits, rows top to bottom, 3 bits per row.
DIGITS = {"0": "111101101101111", "1": "010110010010111", "2": "111001111100111", "3": "111001111001111",
          "4": "101101111001001", "5": "111100111001111", "6": "111100111101111", "7": "111001001001001",
          "8": "111101111101111", "9": "111101111001111"}


def project(points, view, projection, size):
    """World points (n, 3) -> pixel coordinates (n, 2) (origin top-left) and a visible mask."""
    homogeneous = np.c_[points, np.ones(len(points))]
    clip = homogeneous @ (np.asarray(projection) @ np.asarray(view)).T
    w = clip[:, 3]
    visible = w > 1e-9
    ndc = clip[:, :2] / np.where(visible, w, 1.0)[:, None]
    x = (ndc[:, 0] + 1) / 2 * size[0]
    y = (1 - (ndc[:, 1] + 1) / 2) * size[1]
    return np.c_[x, y], visible


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


def draw_label(tile, text, scale=3, margin=6):
    x = margin
    for ch in text:
        pattern = DIGITS.get(ch)
        if pattern is not None:
            for row in range(5):
                for col in range(3):
                    if pattern[3 * row + col] == "1":
                        tile[margin + row * scale:margin + (row + 1) * scale, x + col * scale:x + (col + 1) * scale] = LABEL
        x += 4 * scale


def render(tiles, view, projection, view_size, tile_width=320, columns=None):
    """tiles: [(world, [polyline (points, 3) per body])] -> RGB image (rows, cols, 3) uint8."""
    tile_height = max(1, int(round(tile_width * view_size[1] / view_size[0])))
    columns = columns or int(np.ceil(np.sqrt(len(tiles))))
    rows = int(np.ceil(len(tiles) / columns))
    sheet = np.zeros((rows * (tile_height + 2), columns * (tile_width + 2), 3), dtype=np.uint8)
    sheet[:] = 60
    scale = (tile_width / view_size[0], tile_height / view_size[1])
    for k, (world, polylines) in enumerate(tiles):
        tile = np.zeros((tile_height, tile_width, 3), dtype=np.uint8)
        tile[:] = BACKGROUND
        for b, polyline in enumerate(polylines):
            pixels, visible = project(np.asarray(polyline, dtype=float), view, projection, view_size)
            pixels *= scale
            for i in range(len(pixels) - 1):
                if visible[i] and visible[i + 1]:
                    draw_line(tile, pixels[i], pixels[i + 1], PATH_COLOURS[b % len(PATH_COLOURS)])
        draw_label(tile, str(world))
        r, c = divmod(k, columns)
        y, x = r * (tile_height + 2) + 1, c * (tile_width + 2) + 1
        sheet[y:y + tile_height, x:x + tile_width] = tile
    return sheet


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
