"""What the two letter examples share: a flat pachinko board (back board, glass, side walls, floor),
staggered rows of pegs, a row of slots with a coloured tile per letter, and the blocky letters that
fall through it as COMPOUND bodies. Everything moves in the XZ plane between the back board and a
front glass pane (a collider only, not rendered)."""
import math
from collections import namedtuple

from example_kit import box, cylinder, material, rigid_body

CHANNEL_HALF_DEPTH = 0.07
LETTER_DEPTH, LETTER_WIDTH, LETTER_HEIGHT, STROKE = 0.1, 0.36, 0.46, 0.08
LETTER_MASS = 0.5
SLOT_WIDTH, SLOT_WALL_HEIGHT, SLOT_WALL_THICKNESS = 0.62, 0.55, 0.04
PEG_RADIUS, PEG_ROW_SPACING, PEG_COLUMN_SPACING = 0.05, 0.6, 0.8
PEG_BOTTOM_ROW_Z = 1.2

WALL_BUMP_REACH = 0.45  # how far a bump stands out of its wall

# A board: its word (one slot per letter), height, number of peg rows, and whether the side walls
# carry a bump at every other row.
Board = namedtuple("Board", "word height peg_rows wall_bumps", defaults=(False,))


def board_width(board):
    return SLOT_WIDTH * len(board.word) + 0.1


def slot_centre_x(board, i):
    return (i - (len(board.word) - 1) / 2) * SLOT_WIDTH


def letter_parts(char):
    """Boxes (size, offset, euler) spelling `char` in a blocky font, in a LETTER_WIDTH x
    LETTER_HEIGHT cell centred on the origin; strokes STROKE wide, LETTER_DEPTH deep along Y."""
    w, h, s, d = LETTER_WIDTH, LETTER_HEIGHT, STROKE, LETTER_DEPTH
    left, right, top, bottom = -(w - s) / 2, (w - s) / 2, (h - s) / 2, -(h - s) / 2

    def bar(x0, z0, x1, z1):
        """A stroke from stroke centre (x0, z0) to (x1, z1), square ends, any angle."""
        length = math.hypot(x1 - x0, z1 - z0) + s
        angle = -math.atan2(z1 - z0, x1 - x0)   # about +Y, which turns +X towards -Z
        return (length, d, s), ((x0 + x1) / 2, 0, (z0 + z1) / 2), (0, angle, 0)

    glyphs = {
        "W": [bar(left, top, left, bottom), bar(right, top, right, bottom), bar(0, 0, 0, bottom + s),
              bar(left + s, bottom, right - s, bottom)],
        "O": [bar(left, top - s, left, bottom + s), bar(right, top - s, right, bottom + s),
              bar(left, top, right, top), bar(left, bottom, right, bottom)],
        "R": [bar(left, top, left, bottom), bar(left + s, top, right - s, top), bar(right, top - s, right, s),
              bar(left + s, 0, right - s, 0), bar(0.0, -s, right, bottom)],
        "L": [bar(left, top, left, bottom + s), bar(left, bottom, right, bottom)],
        "D": [bar(left, top, left, bottom), bar(left + s, top, right - s, top),
              bar(left + s, bottom, right - s, bottom), bar(right, top - s, right, bottom + s)],
        "S": [bar(left, top, right, top), bar(left, top - s, left, s / 2), bar(left + s, 0, right - s, 0),
              bar(right, -s / 2, right, bottom + s), bar(left, bottom, right, bottom)],
        "I": [bar(0, top - s, 0, bottom + s), bar(left, top, right, top), bar(left, bottom, right, bottom)],
        "G": [bar(left, top - s, left, bottom + s), bar(left, top, right, top), bar(left, bottom, right, bottom),
              bar(right, bottom + s, right, 0), bar(0, 0, right - s, 0)],
        "A": [bar(left, top - s, left, bottom), bar(right, top - s, right, bottom), bar(left, top, right, top),
              bar(left + s, 0, right - s, 0)],
        "P": [bar(left, top, left, bottom), bar(left + s, top, right - s, top), bar(right, top - s, right, s),
              bar(left + s, 0, right - s, 0)],
        "H": [bar(left, top, left, bottom), bar(right, top, right, bottom), bar(left + s, 0, right - s, 0)],
    }
    return glyphs[char]


def build_board(board, mats):
    """Back board, glass, side walls and floor. The glass is a collider only: wire, not rendered."""
    width = board_width(board)
    floor = box("Floor", (width, 2 * CHANNEL_HALF_DEPTH + 0.2, 0.1), location=(0, 0, -0.05), mat=mats["frame"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.6)
    back = box("Board", (width, 0.04, board.height), location=(0, CHANNEL_HALF_DEPTH + 0.02, board.height / 2),
               mat=mats["board"])
    rigid_body(back, "PASSIVE", "BOX", friction=0.1)
    glass = box("Glass", (width, 0.04, board.height), location=(0, -CHANNEL_HALF_DEPTH - 0.02, board.height / 2))
    glass.display_type, glass.hide_render = "WIRE", True
    rigid_body(glass, "PASSIVE", "BOX", friction=0.0)
    for side, sign in (("L", -1), ("R", 1)):
        wall = box(f"SideWall{side}", (0.05, 2 * CHANNEL_HALF_DEPTH, board.height),
                   location=(sign * (width / 2 + 0.025), 0, board.height / 2), mat=mats["frame"])
        rigid_body(wall, "PASSIVE", "BOX", friction=0.2)


def build_pegs(board, mats):
    """Staggered rows of passive cylinders across the channel (their axis along Y)."""
    # a peg closer to a side wall than a letter's diagonal would wedge letters against the wall
    usable = board_width(board) / 2 - PEG_RADIUS - math.hypot(LETTER_WIDTH, LETTER_HEIGHT) - 0.02
    for row in range(board.peg_rows):
        z = PEG_BOTTOM_ROW_Z + row * PEG_ROW_SPACING
        offset = 0.0 if row % 2 == 0 else PEG_COLUMN_SPACING / 2
        count = int(usable // PEG_COLUMN_SPACING) + 1
        for col in range(-count, count + 1):
            x = col * PEG_COLUMN_SPACING + offset
            if abs(x) > usable:
                continue
            peg = cylinder(f"Peg_r{row}_c{col + count:02d}", PEG_RADIUS, 2 * CHANNEL_HALF_DEPTH, location=(x, 0, z),
                           rotation=(math.pi / 2, 0, 0), mat=mats["peg"])
            rigid_body(peg, "PASSIVE", "CYLINDER", friction=0.3, restitution=0.4)
        if board.wall_bumps and row % 2 == 1:
            build_wall_bumps(board, row, z, mats)


def build_wall_bumps(board, row, z, mats):
    """Square bumps set corner-first into both side walls at the height of a row whose outermost
    pegs are far from the walls. Without them the strip between the outermost pegs and a wall has
    nothing in it for every other row: a letter that drifts into it falls almost straight down to
    the end slot (on the tall board, two thirds or more of the letters starting farthest out did).
    Their faces slope at 45 degrees, so nothing rests on them, and the gap left between a bump's
    corner and the nearest pegs is wider than the rows' own, so nothing wedges there (round bumps
    as far out pinched letters between their undersides and the pegs below)."""
    wall_face = board_width(board) / 2
    side_length = WALL_BUMP_REACH * math.sqrt(2)
    for side, sign in (("L", -1), ("R", 1)):
        bump = box(f"WallBump{side}_r{row:02d}", (side_length, 2 * CHANNEL_HALF_DEPTH, side_length),
                   location=(sign * wall_face, 0, z), rotation=(0, math.pi / 4, 0), mat=mats["frame"])
        rigid_body(bump, "PASSIVE", "BOX", friction=0.3, restitution=0.4)


def build_slots(board, mats):
    """Dividers between the slots; each slot has a floor tile in its letter's colour, for the eye
    and for drawing screen boxes."""
    for i in range(1, len(board.word)):
        x = slot_centre_x(board, i) - SLOT_WIDTH / 2
        divider = box(f"SlotDivider{i}", (SLOT_WALL_THICKNESS, 2 * CHANNEL_HALF_DEPTH, SLOT_WALL_HEIGHT),
                      location=(x, 0, SLOT_WALL_HEIGHT / 2), mat=mats["frame"])
        rigid_body(divider, "PASSIVE", "BOX", friction=0.3)
    for i, char in enumerate(board.word):
        tile = box(f"Slot{i + 1}_{char}", (SLOT_WIDTH - SLOT_WALL_THICKNESS, 2 * CHANNEL_HALF_DEPTH, 0.01),
                   location=(slot_centre_x(board, i), 0, 0.005), mat=mats[f"letter{i % 3}"])
        rigid_body(tile, "PASSIVE", "BOX", friction=0.6)


def build_peg_board(board):
    """The whole board (frame, pegs, slots) in the materials both examples use; returns them, for
    the letters."""
    mats = board_materials()
    build_board(board, mats)
    build_pegs(board, mats)
    build_slots(board, mats)
    return mats


def board_materials():
    """The materials both boards use."""
    return {k: material(k, rgb) for k, rgb in {
        "frame": (0.3, 0.3, 0.35), "board": (0.9, 0.88, 0.82), "peg": (0.75, 0.75, 0.8),
        "letter0": (0.85, 0.2, 0.15), "letter1": (0.15, 0.45, 0.85), "letter2": (0.95, 0.7, 0.1)}.items()}
