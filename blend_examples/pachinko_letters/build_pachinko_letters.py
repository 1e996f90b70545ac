"""Builds the pachinko-letters example: the letters of WORLDS fall through a board of pegs into a
row of slots.

Goal: "every letter lands in its own slot, so the slots spell WORLDS". A random run puts one or two
letters in place; the paper's user got all of them there by refining one or two letters at a time.

Run:  blender -b --factory-startup --python blend_examples/pachinko_letters/build_pachinko_letters.py -- OUT.blend
Letters are COMPOUND rigid bodies (Blender 3.4's "Compound Parent" shape): the letter object holds
the visible mesh, its children are the BOX parts it collides with. Everything is made from nothing
with Blender's own rigid-body settings; variation ranges are ID custom properties (mwb_*) that the
Many-Worlds add-on reads.
"""
import math
import os
import sys

import bmesh
import bpy
from mathutils import Euler, Matrix, Vector

FPS = 24
FRAME_START, FRAME_END = 1, 144         # 6 s: the letters are at rest in the slots after 4-5 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 10
THIN_OBJECT, THIN_MARGIN = 0.1, 0.0005   # metres; see rigid_body()
WORLD_COUNT, SEED = 1000, 1

WORD = "WORLDS"
# Flat, like a real pachinko machine: everything moves in the XZ plane between a back board and a
# front glass pane (not rendered).
CHANNEL_HALF_DEPTH = 0.07
LETTER_DEPTH, LETTER_WIDTH, LETTER_HEIGHT, STROKE = 0.1, 0.36, 0.46, 0.08
LETTER_MASS = 0.5
SLOT_WIDTH, SLOT_WALL_HEIGHT, SLOT_WALL_THICKNESS = 0.62, 0.55, 0.04
BOARD_WIDTH, BOARD_HEIGHT = SLOT_WIDTH * len(WORD) + 0.1, 5.2
PEG_RADIUS, PEG_ROWS, PEG_ROW_SPACING, PEG_COLUMN_SPACING = 0.05, 5, 0.6, 0.8
PEG_BOTTOM_ROW_Z = 1.2
LETTER_START_Z = (4.3, 4.9)             # alternate letters start at two heights so they do not collide at once


# --- generic helpers ---------------------------------------------------------------------------

def output_path():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        sys.exit(f"usage: blender -b --factory-startup --python {os.path.basename(__file__)} -- OUTPUT.blend")
    return os.path.abspath(argv[0])


def material(name, rgb):
    mat = bpy.data.materials.new(name)
    mat.diffuse_color = (*rgb, 1.0)    # the solid-shading viewport colour
    mat.use_nodes = True
    mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (*rgb, 1.0)
    return mat


def mesh_object(name, build, location=(0, 0, 0), rotation=(0, 0, 0), mat=None):
    """An object whose mesh `build(bm)` fills; origin at the shape's centre, unit scale, so the
    rigid-body shape Blender derives from the bounds is the shape we mean."""
    bm = bmesh.new()
    build(bm)
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    if mat:
        mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    obj.location, obj.rotation_euler = location, rotation
    bpy.context.scene.collection.objects.link(obj)
    return obj


def box(name, size, **kw):
    return mesh_object(name, lambda bm: bmesh.ops.create_cube(bm, size=1.0, matrix=Matrix.Diagonal((*size, 1.0))), **kw)




def cylinder(name, radius, depth, **kw):
    return mesh_object(name, lambda bm: bmesh.ops.create_cone(
        bm, cap_ends=True, segments=32, radius1=radius, radius2=radius, depth=depth), **kw)


def smallest_extent(obj):
    """The object's thinnest bounding-box side, from its mesh (objects here have unit scale)."""
    coords = [v.co for v in obj.data.vertices]
    return min(max(c[i] for c in coords) - min(c[i] for c in coords) for i in range(3))


def rigid_body(obj, body_type, shape, mass=1.0, friction=0.5, restitution=0.0, damping=(0.04, 0.1)):
    bpy.context.view_layer.objects.active = obj
    bpy.ops.rigidbody.object_add(type=body_type)
    rb = obj.rigid_body
    rb.collision_shape, rb.mass, rb.friction, rb.restitution = shape, mass, friction, restitution
    rb.linear_damping, rb.angular_damping = damping
    # While use_margin is off Blender uses a hidden 4 cm margin: inside BOX and CYLINDER shapes, which
    # breaks those thinner than 8 cm, and outside CONE and hull shapes. Such objects get a tiny
    # explicit margin instead (the engine adds an explicit margin outside every shape; 0.5 mm is
    # harmless there). Everything else keeps the default, which the engine ignores.
    if shape in ("CONE", "CONVEX_HULL") or smallest_extent(obj) < THIN_OBJECT:
        rb.use_margin, rb.collision_margin = True, THIN_MARGIN
    return rb


def compound(name, parts, location, rotation=(0, 0, 0), mat=None, mass=1.0, **rigid):
    """An ACTIVE COMPOUND body made of boxes. `parts` are (size, offset, euler) in the body's frame
    with `location` as reference point. The parent carries the visible mesh; each part is a child
    with its own BOX rigid body (how Blender builds compounds), drawn as wire and not rendered.
    The origin goes to the volume centroid of the parts: Blender puts the centre of mass at the
    origin, the engine computes it from the shapes, and this way both agree."""
    volumes = [s[0] * s[1] * s[2] for s, _, _ in parts]
    centroid = sum((Vector(o) * v for (_, o, _), v in zip(parts, volumes)), Vector()) / sum(volumes)
    boxes = [(s, Vector(o) - centroid, Euler(e)) for s, o, e in parts]

    def all_boxes(bm):
        for size, offset, euler in boxes:
            placement = Matrix.Translation(offset) @ euler.to_matrix().to_4x4() @ Matrix.Diagonal((*size, 1.0))
            bmesh.ops.create_cube(bm, size=1.0, matrix=placement)

    parent = mesh_object(name, all_boxes, location=Vector(location) + Euler(rotation).to_matrix() @ centroid,
                         rotation=rotation, mat=mat)
    rigid_body(parent, "ACTIVE", "COMPOUND", mass=mass, **rigid)
    for i, (size, offset, euler) in enumerate(boxes):
        part = box(f"{name}.part{i}", size, location=offset, rotation=euler)
        part.parent = parent
        part.display_type, part.hide_render, part.hide_select = "WIRE", True, True
        rigid_body(part, "ACTIVE", "BOX", mass=mass / len(boxes), **rigid)
    return parent


def variation(obj, location=(0, 0, 0), rotation=(0, 0, 0), linear_velocity=(0, 0, 0), angular_velocity=(0, 0, 0)):
    """Symmetric ranges [-r, +r] per axis, world frame, added to the object's initial state."""
    ranges = {}
    for key, r in (("location", location), ("rotation", rotation),
                   ("linear_velocity", linear_velocity), ("angular_velocity", angular_velocity)):
        ranges[f"{key}_min"], ranges[f"{key}_max"] = [-v for v in r], list(r)
    # Stored where the add-on's Object.mwb_variation property group keeps them: Blender maps this
    # ID group onto the registered group, so the script needs no add-on to run.
    obj["mwb_variation"] = ranges


def look_at(obj, target):
    obj.rotation_euler = (Vector(target) - obj.location).to_track_quat("-Z", "Y").to_euler()


def camera_and_lights(location, target, lens=35.0):
    scene = bpy.context.scene
    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    cam.data.lens = lens
    cam.location = location
    look_at(cam, target)
    scene.collection.objects.link(cam)
    scene.camera = cam
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.data.energy, sun.data.angle = 3.0, math.radians(10)
    sun.rotation_euler = Euler((math.radians(40), math.radians(15), math.radians(30)))
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("World")
    world.color = (0.05, 0.05, 0.06)
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.25, 0.27, 0.3, 1.0)
    scene.world = world


def scene_settings(duration_s):
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.frame_start, scene.frame_end = FRAME_START, FRAME_END
    bpy.ops.rigidbody.world_add()
    rbw = scene.rigidbody_world
    rbw.substeps_per_frame, rbw.solver_iterations = SUBSTEPS, SOLVER_ITERATIONS
    rbw.point_cache.frame_start, rbw.point_cache.frame_end = FRAME_START, FRAME_END
    # The add-on's Scene.mwb settings, set the same way.
    scene["mwb"] = {"world_count": WORLD_COUNT, "seed": SEED, "duration_s": duration_s}




# --- letters ------------------------------------------------------------------------------------

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
    }
    return glyphs[char]


def build_letters(mats):
    """One compound body per letter, each above its own slot."""
    for i, char in enumerate(WORD):
        x = slot_centre_x(i)
        z = LETTER_START_Z[i % 2]
        letter = compound(f"Letter{i + 1}_{char}", letter_parts(char), location=(x, 0, z), mat=mats[f"letter{i % 3}"],
                          mass=LETTER_MASS, friction=0.4, restitution=0.3)
        # +-2 cm and a small in-plane spin; the pegs turn these into very different falls
        variation(letter, location=(0.02, 0.005, 0.02), rotation=(0.0, 0.05, 0.0), angular_velocity=(0.0, 0.5, 0.0))


# --- board --------------------------------------------------------------------------------------

def slot_centre_x(i):
    return (i - (len(WORD) - 1) / 2) * SLOT_WIDTH


def build_board(mats):
    """Back board, glass, side walls and floor. The glass is a collider only: wire, not rendered."""
    floor = box("Floor", (BOARD_WIDTH, 2 * CHANNEL_HALF_DEPTH + 0.2, 0.1), location=(0, 0, -0.05), mat=mats["frame"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.6)
    board = box("Board", (BOARD_WIDTH, 0.04, BOARD_HEIGHT), location=(0, CHANNEL_HALF_DEPTH + 0.02, BOARD_HEIGHT / 2),
                mat=mats["board"])
    rigid_body(board, "PASSIVE", "BOX", friction=0.1)
    glass = box("Glass", (BOARD_WIDTH, 0.04, BOARD_HEIGHT), location=(0, -CHANNEL_HALF_DEPTH - 0.02, BOARD_HEIGHT / 2))
    glass.display_type, glass.hide_render = "WIRE", True
    rigid_body(glass, "PASSIVE", "BOX", friction=0.0)
    for side, sign in (("L", -1), ("R", 1)):
        wall = box(f"SideWall{side}", (0.05, 2 * CHANNEL_HALF_DEPTH, BOARD_HEIGHT),
                   location=(sign * (BOARD_WIDTH / 2 + 0.025), 0, BOARD_HEIGHT / 2), mat=mats["frame"])
        rigid_body(wall, "PASSIVE", "BOX", friction=0.2)


def build_pegs(mats):
    """Staggered rows of passive cylinders across the channel (their axis along Y)."""
    # a peg closer to a side wall than a letter's diagonal would wedge letters against the wall
    usable = BOARD_WIDTH / 2 - PEG_RADIUS - math.hypot(LETTER_WIDTH, LETTER_HEIGHT) - 0.02
    for row in range(PEG_ROWS):
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


def build_slots(mats):
    """Dividers between the slots; each slot has a floor tile with its letter's colour for the eye
    and for drawing screen boxes."""
    for i in range(1, len(WORD)):
        x = slot_centre_x(i) - SLOT_WIDTH / 2
        divider = box(f"SlotDivider{i}", (SLOT_WALL_THICKNESS, 2 * CHANNEL_HALF_DEPTH, SLOT_WALL_HEIGHT),
                      location=(x, 0, SLOT_WALL_HEIGHT / 2), mat=mats["frame"])
        rigid_body(divider, "PASSIVE", "BOX", friction=0.3)
    for i, char in enumerate(WORD):
        tile = box(f"Slot{i + 1}_{char}", (SLOT_WIDTH - SLOT_WALL_THICKNESS, 2 * CHANNEL_HALF_DEPTH, 0.01),
                   location=(slot_centre_x(i), 0, 0.005), mat=mats[f"letter{i % 3}"])
        rigid_body(tile, "PASSIVE", "BOX", friction=0.6)


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "pachinko_letters"
    scene_settings(duration_s=0.0)
    mats = {k: material(k, rgb) for k, rgb in {
        "frame": (0.3, 0.3, 0.35), "board": (0.9, 0.88, 0.82), "peg": (0.75, 0.75, 0.8),
        "letter0": (0.85, 0.2, 0.15), "letter1": (0.15, 0.45, 0.85), "letter2": (0.95, 0.7, 0.1)}.items()}
    build_board(mats)
    build_pegs(mats)
    build_slots(mats)
    build_letters(mats)
    camera_and_lights(location=(0.0, -9.5, 2.6), target=(0, 0, 2.5), lens=35)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
