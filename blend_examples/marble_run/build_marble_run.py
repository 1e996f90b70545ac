"""Builds the marble-run example, the paper's "refrigerator toy": a marble rolls down chutes and
drops into hinged cups that tip it on, left or right, to the next chute or out of the run.

Goal: "the marble tips Cup1, Cup2, Cup3 and Cup4 in turn and ends in the goal basket". Each cup
tips one way or the other depending on where the marble lands in it, so a random run completes the
chain roughly one time in sixteen: sampling finds it, refinement makes it quick.

Run:  blender -b --factory-startup --python blend_examples/marble_run/build_marble_run.py -- OUT.blend
Everything is made from nothing with Blender's own rigid-body settings; variation ranges are ID
custom properties (mwb_*) that the Many-Worlds add-on reads.
"""
import math
import os
import sys

import bmesh
import bpy
from mathutils import Euler, Matrix, Vector

FPS = 24
FRAME_START, FRAME_END = 1, 192         # 8 s: a full chain reaches the basket after about 6.5 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 20    # small fast marble: 240 Hz, extra iterations for the hinges
THIN_OBJECT, THIN_MARGIN = 0.1, 0.0005   # metres; see rigid_body()
WORLD_COUNT, SEED = 500, 1

# The toy is flat, as on a fridge door: everything moves in the XZ plane between a back board and a
# front glass pane (not rendered) that keep the marble in the plane.
CHANNEL_HALF_DEPTH = 0.05               # inner faces of board and pane at y = -+0.05
MARBLE_RADIUS, MARBLE_MASS = 0.035, 0.1
PIECE_THICKNESS = 0.02
DROP_GAP = 0.09                         # between a chute's end and its stop wall; the marble drops through
# The gap's centre sits this far short of the cup's hinge: the marble still carries a little speed
# along the chute when it lands, and this offset makes each cup tip either way about equally often.
LANDING_SHIFT = 0.01
STOP_WALL_HEIGHT = 0.2
BOARD_WIDTH, BOARD_HEIGHT = 1.4, 2.6

# Cups: a flat-bottomed U with a keel under it. The hinge sits a little above the cup's own centre of
# mass, so an empty cup hangs upright, but below the marble's centre once it is inside, so a full cup
# is unstable and tips towards whichever side the marble landed on.
CUP_INNER_WIDTH, CUP_WALL_HEIGHT, CUP_DEPTH = 0.16, 0.075, 0.08
CUP_MASS, CUP_PIVOT_ABOVE_COM = 0.03, 0.012
CUP_TIP_LIMIT = math.radians(110)
CUP_CLEARANCE = 0.17                    # radius around a hinge that the swinging cup sweeps, with margin

# (name, hinge x, hinge z, the side it must tip to for the chain: +1 right, -1 left)
CUPS = (("Cup1", -0.3, 2.2, +1), ("Cup2", 0.3, 1.7, -1), ("Cup3", -0.3, 1.2, +1), ("Cup4", 0.3, 0.7, -1))
LEVEL_DROP = 0.5


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




def sphere(name, radius, **kw):
    return mesh_object(name, lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=radius),
                       **kw)






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
    """An ACTIVE COMPOUND body made of boxes. `parts` are (size, offset) in the body's frame with
    `location` as reference point. The parent carries the visible mesh; each part is a child with
    its own BOX rigid body (how Blender builds compounds), drawn as wire and not rendered.
    The origin goes to the volume centroid of the parts: Blender puts the centre of mass at the
    origin, the engine computes it from the shapes, and this way both agree."""
    volumes = [s[0] * s[1] * s[2] for s, _ in parts]
    centroid = sum((Vector(o) * v for (_, o), v in zip(parts, volumes)), Vector()) / sum(volumes)
    rot = Euler(rotation)
    boxes = [(s, Vector(o) - centroid) for s, o in parts]

    def all_boxes(bm):
        for size, offset in boxes:
            bmesh.ops.create_cube(bm, size=1.0, matrix=Matrix.Translation(offset) @ Matrix.Diagonal((*size, 1.0)))

    parent = mesh_object(name, all_boxes, location=Vector(location) + rot.to_matrix() @ centroid, rotation=rotation,
                         mat=mat)
    rigid_body(parent, "ACTIVE", "COMPOUND", mass=mass, **rigid)
    for i, (size, offset) in enumerate(boxes):
        part = box(f"{name}.part{i}", size, location=offset)
        part.parent = parent
        part.display_type, part.hide_render, part.hide_select = "WIRE", True, True
        rigid_body(part, "ACTIVE", "BOX", mass=mass / len(boxes), **rigid)
    return parent, centroid


def constraint(name, kind, obj1, obj2, location, rotation=(0, 0, 0), **settings):
    """A Rigid Body Constraint on a new empty; `settings` are RigidBodyConstraint attributes."""
    empty = bpy.data.objects.new(name, None)
    empty.empty_display_type, empty.empty_display_size = "ARROWS", 0.1
    empty.location, empty.rotation_euler = location, rotation
    bpy.context.scene.collection.objects.link(empty)
    bpy.context.view_layer.objects.active = empty
    bpy.ops.rigidbody.constraint_add(type=kind)
    con = empty.rigid_body_constraint
    con.object1, con.object2 = obj1, obj2
    for key, value in settings.items():
        setattr(con, key, value)
    return con


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



# --- the scene ---------------------------------------------------------------------------------

def build_frame(mats):
    """Floor, end walls, back board and front glass, so a marble that leaves the run stays in the box.
    The glass is a collider only: wire in the viewport, not rendered."""
    floor = box("Floor", (BOARD_WIDTH, 0.4, 0.05), location=(0, 0, -0.025), mat=mats["floor"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.6)
    for side, sign in (("L", -1), ("R", 1)):
        wall = box(f"EndWall{side}", (PIECE_THICKNESS, 2 * CHANNEL_HALF_DEPTH, BOARD_HEIGHT),
                   location=(sign * (BOARD_WIDTH - PIECE_THICKNESS) / 2, 0, BOARD_HEIGHT / 2), mat=mats["board"])
        rigid_body(wall, "PASSIVE", "BOX")
    board = box("Board", (BOARD_WIDTH, PIECE_THICKNESS, BOARD_HEIGHT),
                location=(0, CHANNEL_HALF_DEPTH + PIECE_THICKNESS / 2, BOARD_HEIGHT / 2), mat=mats["board"])
    rigid_body(board, "PASSIVE", "BOX", friction=0.2)
    glass = box("Glass", (BOARD_WIDTH, PIECE_THICKNESS, BOARD_HEIGHT),
                location=(0, -CHANNEL_HALF_DEPTH - PIECE_THICKNESS / 2, BOARD_HEIGHT / 2))
    glass.display_type, glass.hide_render = "WIRE", True
    rigid_body(glass, "PASSIVE", "BOX", friction=0.0)


def chute(name, start, end, mats):
    """A passive chute whose top surface runs from `start` to `end` (x, z), with a stop wall beyond the
    low end that catches the marble so it drops, slowed, through the gap into the cup below."""
    start, end = Vector((start[0], 0, start[1])), Vector((end[0], 0, end[1]))
    along = end - start
    tilt = math.atan2(-along.z, abs(along.x)) * (1 if along.x > 0 else -1)   # about +Y, downhill towards end
    half_normal = Vector((math.sin(tilt), 0, math.cos(tilt))) * (PIECE_THICKNESS / 2)
    slab = box(name, (along.length, 2 * CHANNEL_HALF_DEPTH, PIECE_THICKNESS), location=(start + end) / 2 - half_normal,
               rotation=(0, tilt, 0), mat=mats["chute"])
    rigid_body(slab, "PASSIVE", "BOX", friction=0.3)
    side = 1 if along.x > 0 else -1
    # reaches below the chute's end: a fast marble leaves the chute on a parabola and would pass under
    wall = box(f"{name}Stop", (PIECE_THICKNESS, 2 * CHANNEL_HALF_DEPTH, STOP_WALL_HEIGHT),
               location=(end.x + side * (DROP_GAP + PIECE_THICKNESS / 2), 0, end.z - 0.07 + STOP_WALL_HEIGHT / 2),
               mat=mats["chute"])
    rigid_body(wall, "PASSIVE", "BOX", friction=0.3, restitution=0.0)


def cup(name, hinge_x, hinge_z, mats):
    """A hinged compound cup (bottom, two walls, keel) turning about the Y axis through its hinge."""
    half = CUP_INNER_WIDTH / 2 + PIECE_THICKNESS / 2
    parts = [((CUP_INNER_WIDTH + 2 * PIECE_THICKNESS, CUP_DEPTH, PIECE_THICKNESS), (0, 0, 0)),
             ((PIECE_THICKNESS, CUP_DEPTH, CUP_WALL_HEIGHT), (-half, 0, (CUP_WALL_HEIGHT + PIECE_THICKNESS) / 2)),
             ((PIECE_THICKNESS, CUP_DEPTH, CUP_WALL_HEIGHT), (half, 0, (CUP_WALL_HEIGHT + PIECE_THICKNESS) / 2)),
             ((0.06, CUP_DEPTH, 0.04), (0, 0, -0.03))]
    # place the cup so that its centre of mass ends up CUP_PIVOT_ABOVE_COM under the hinge
    volumes = [s[0] * s[1] * s[2] for s, _ in parts]
    com_z = sum(o[2] * v for (_, o), v in zip(parts, volumes)) / sum(volumes)
    body, _ = compound(name, parts, location=(hinge_x, 0, hinge_z - CUP_PIVOT_ABOVE_COM - com_z), mat=mats["cup"],
                       mass=CUP_MASS, friction=0.4, damping=(0.1, 0.8))
    # the empty's local Z is the hinge axis: turn it onto world Y
    constraint(f"{name}Hinge", "HINGE", bpy.data.objects["Board"], body, location=(hinge_x, 0, hinge_z),
               rotation=(math.pi / 2, 0, 0), use_limit_ang_z=True,
               limit_ang_z_lower=-CUP_TIP_LIMIT, limit_ang_z_upper=CUP_TIP_LIMIT)
    return body


def build_run(mats):
    """A start chute into Cup1, then one chute per cup, each starting under the rim the cup must tip
    over and ending above the next cup (or the goal basket), so the run zigzags down the board."""
    _, x0, z0, _ = CUPS[0]
    chute("Chute0", (x0 - 0.35, z0 + 0.28), (x0 - DROP_GAP / 2 - LANDING_SHIFT, z0 + 0.22), mats)
    for i, (name, x, z, side) in enumerate(CUPS):
        cup(name, x, z, mats)
        target_x = CUPS[i + 1][1] if i + 1 < len(CUPS) else -x
        # starts under the hinge, below the circle the swinging cup sweeps, to catch the marble wherever
        # it leaves the rim; slopes down towards the next cup
        chute(f"Chute{i + 1}", (x - side * 0.02, z - CUP_CLEARANCE - 0.01),
              (target_x - side * (DROP_GAP / 2 + LANDING_SHIFT), z - CUP_CLEARANCE - 0.09), mats)
    basket_x, basket_z = -CUPS[-1][1], CUPS[-1][2] - LEVEL_DROP
    for part, size, offset in (("Bottom", (0.24, 0.1, 0.02), (0, 0, 0)), ("WallL", (0.02, 0.1, 0.1), (-0.11, 0, 0.05)),
                               ("WallR", (0.02, 0.1, 0.1), (0.11, 0, 0.05))):
        piece = box(f"GoalBasket{part}", size, location=(basket_x + offset[0], 0, basket_z + offset[2]),
                    mat=mats["goal"])
        rigid_body(piece, "PASSIVE", "BOX", friction=0.6)


def build_marble(mats):
    _, x0, z0, _ = CUPS[0]
    marble = sphere("Marble", MARBLE_RADIUS, location=(x0 - 0.3, 0, z0 + 0.27 + MARBLE_RADIUS), mat=mats["marble"])
    rigid_body(marble, "ACTIVE", "SPHERE", mass=MARBLE_MASS, friction=0.3, restitution=0.1, damping=(0.0, 0.05))
    # +-2 cm along the chute and a nudge either way decide how it meets each cup; y stays in the channel
    variation(marble, location=(0.02, 0.005, 0.0), linear_velocity=(0.05, 0.0, 0.0), angular_velocity=(0.0, 1.0, 0.0))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "marble_run"
    scene_settings(duration_s=0.0)
    mats = {k: material(k, rgb) for k, rgb in {
        "floor": (0.45, 0.45, 0.45), "board": (0.85, 0.85, 0.8), "chute": (0.2, 0.45, 0.8),
        "cup": (0.9, 0.55, 0.1), "goal": (0.2, 0.7, 0.25), "marble": (0.8, 0.1, 0.15)}.items()}
    build_frame(mats)
    build_run(mats)
    build_marble(mats)
    camera_and_lights(location=(0.6, -5.4, 1.5), target=(0, 0, 1.3), lens=35)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
