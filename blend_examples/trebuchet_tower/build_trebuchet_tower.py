"""Builds the trebuchet-and-tower example: a counterweight trebuchet throws a rock at a tower of
192 stacked blocks, with three bystanders standing around the tower.

Goals (queries in the paper): "the rock hits the tower" and "... the falling blocks miss the
bystanders".

Mechanism, the simplest that works: the arm (beam, counterweight and a cup joined by FIXED
constraints) turns on a HINGE; the rock rests in the cup on the arm's leading face, at its tip. When the falling
counterweight has swung the arm up, the hinge's upper limit stops it dead and the rock flies on.

Run:  blender -b --factory-startup --python blend_examples/trebuchet_tower/build_trebuchet_tower.py -- OUT.blend
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
FRAME_START, FRAME_END = 1, 168         # 7 s: swing, flight, and the tower has finished falling
SUBSTEPS, SOLVER_ITERATIONS = 10, 10
THIN_OBJECT, THIN_MARGIN = 0.1, 0.0005   # metres; see rigid_body()
WORLD_COUNT, SEED = 300, 1

# trebuchet, throwing along +X; the arm swings in the XZ plane about the Y axis
PIVOT = Vector((0.0, 0.0, 3.2))
LONG_ARM, SHORT_ARM, BEAM_SECTION = 4.0, 1.2, 0.15
COUNTERWEIGHT_SIZE, COUNTERWEIGHT_MASS = 0.9, 300.0
BEAM_MASS = 50.0
CUP_LENGTH, CUP_WIDTH, PLATE, CUP_MASS = 0.5, 0.5, 0.04, 5.0
COCKED_ANGLE = math.radians(225)        # long arm direction at the start, from +X towards +Z
RELEASE_ANGLE = math.radians(120)       # the hinge limit stops the arm here: a throw 30 degrees up
ROCK_RADIUS, ROCK_MASS = 0.18, 20.0
FRAME_HALF_GAP = 0.55                   # uprights either side of the arm, clear of the counterweight

# tower: 12 layers of 16 blocks in a pinwheel ring; alternate layers are mirrored so joints overlap
TOWER_CENTRE = Vector((11.0, 0.0, 0.0))        # the rock, thrown as built, meets the tower at about 2.7 m
LAYERS, BLOCKS_PER_SIDE = 12, 4
BLOCK_LENGTH, BLOCK_DEPTH, BLOCK_HEIGHT, BLOCK_MASS = 0.5, 0.25, 0.25, 5.0
# (x, y) of the passive figures, within reach of blocks knocked off the tower
BYSTANDERS = ((TOWER_CENTRE.x + 2.6, 0.9), (TOWER_CENTRE.x + 0.8, -2.3), (TOWER_CENTRE.x - 0.6, 2.4))


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


def capsule_geometry(bm, radius, length, rings=8, segments=24):
    """A capsule along local Z, `length` from tip to tip (Blender's CAPSULE shape reads the bounds)."""
    half = length / 2 - radius
    lats = [(-math.pi / 2 + math.pi / 2 * i / rings, -half) for i in range(1, rings + 1)]
    lats += [(math.pi / 2 * i / rings, half) for i in range(rings)]
    grid = [[bm.verts.new((radius * math.cos(lat) * math.cos(2 * math.pi * j / segments),
                           radius * math.cos(lat) * math.sin(2 * math.pi * j / segments),
                           radius * math.sin(lat) + z)) for j in range(segments)] for lat, z in lats]
    bottom, top = bm.verts.new((0, 0, -length / 2)), bm.verts.new((0, 0, length / 2))
    for j in range(segments):
        k = (j + 1) % segments
        bm.faces.new((bottom, grid[0][k], grid[0][j]))
        bm.faces.new((top, grid[-1][j], grid[-1][k]))
        for a, b in zip(grid, grid[1:]):
            bm.faces.new((a[j], a[k], b[k], b[j]))


def capsule(name, radius, length, **kw):
    return mesh_object(name, lambda bm: capsule_geometry(bm, radius, length), **kw)


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




# --- trebuchet ----------------------------------------------------------------------------------

def arm_rotation():
    """The arm's Euler rotation: about +Y, which turns +X towards -Z, so local +X (the long arm)
    points along COCKED_ANGLE and local -Z is the leading face, the way the tip moves."""
    return (0.0, -COCKED_ANGLE, 0.0)


def build_frame(mats):
    """Two passive uprights and a base; the arm hangs between the uprights on its hinge."""
    for side, sign in (("L", -1), ("R", 1)):
        upright = box(f"Upright{side}", (0.3, 0.1, PIVOT.z + 0.2),
                      location=(PIVOT.x, sign * (FRAME_HALF_GAP + 0.05), (PIVOT.z + 0.2) / 2), mat=mats["wood"])
        rigid_body(upright, "PASSIVE", "BOX", friction=0.5)
        skid = box(f"Skid{side}", (3.0, 0.2, 0.2), location=(PIVOT.x, sign * (FRAME_HALF_GAP + 0.05), 0.1),
                   mat=mats["wood"])
        rigid_body(skid, "PASSIVE", "BOX", friction=0.5)


def build_arm(mats):
    """Beam, counterweight and cup joined by FIXED constraints (the heavy parts are plain boxes, so
    their inertia is exact in Blender and in the engine; a Blender COMPOUND takes its inertia from
    the bounding box), hinged to an upright; the hinge stops at RELEASE_ANGLE. The rock rests in
    the cup on the leading face."""
    half = BEAM_SECTION / 2
    rotation = arm_rotation()
    place = Matrix.Translation(PIVOT) @ Euler(rotation).to_matrix().to_4x4()
    beam = box("Arm", (LONG_ARM + SHORT_ARM, BEAM_SECTION, BEAM_SECTION),
               location=place @ Vector(((LONG_ARM - SHORT_ARM) / 2, 0, 0)), rotation=rotation, mat=mats["wood"])
    rigid_body(beam, "ACTIVE", "BOX", mass=BEAM_MASS, friction=0.6, damping=(0.0, 0.02))
    weight = box("Counterweight", (COUNTERWEIGHT_SIZE,) * 3, location=place @ Vector((-SHORT_ARM, 0, 0)),
                 rotation=rotation, mat=mats["iron"])
    rigid_body(weight, "ACTIVE", "BOX", mass=COUNTERWEIGHT_MASS, friction=0.6, damping=(0.0, 0.02))
    # the cup: a plate on the leading face with cheeks either side and a lip at the end, so the rock
    # can neither roll off the narrow beam sideways nor slide off its end before the release
    cup_parts = [((CUP_LENGTH, CUP_WIDTH, PLATE), (LONG_ARM - CUP_LENGTH / 2, 0, -half - PLATE / 2), (0, 0, 0)),
                 ((0.06, CUP_WIDTH, 0.35), (LONG_ARM + 0.03, 0, -half - 0.175), (0, 0, 0))]
    for sign in (-1, 1):
        cup_parts.append(((CUP_LENGTH, PLATE, 0.18), (LONG_ARM - CUP_LENGTH / 2, sign * (CUP_WIDTH - PLATE) / 2,
                                                       -half - PLATE - 0.09), (0, 0, 0)))
    cup = compound("Cup", [(size, place @ Vector(offset) - PIVOT, euler) for size, offset, euler in cup_parts],
                   location=PIVOT, mat=mats["wood"], mass=CUP_MASS, friction=0.6)
    constraint("CounterweightFixed", "FIXED", beam, weight, location=weight.location)
    constraint("CupFixed", "FIXED", beam, cup, location=cup.location)
    # The hinge axis is the empty's local Z, here world -Y. The limits are symmetric: the arm only
    # ever swings one way, and the stop then does not depend on which body's angle a simulator
    # measures (Blender measures object1 relative to object2, the opposite of the usual convention).
    swing = COCKED_ANGLE - RELEASE_ANGLE
    constraint("ArmHinge", "HINGE", bpy.data.objects["UprightR"], beam, location=PIVOT, rotation=(math.pi / 2, 0, 0),
               use_limit_ang_z=True, limit_ang_z_lower=-swing, limit_ang_z_upper=swing)
    rock_at = place @ Vector((LONG_ARM - ROCK_RADIUS - 0.02, 0, -half - PLATE - ROCK_RADIUS - 0.002))
    rock = sphere("Rock", ROCK_RADIUS, location=rock_at, mat=mats["rock"])
    rigid_body(rock, "ACTIVE", "SPHERE", mass=ROCK_MASS, friction=0.6, restitution=0.1)
    # Only the rock varies: a nudge as it sits in the cup changes where it flies, which is what the
    # paper got by varying the release time; the jointed arm gets no variation, since moving one of
    # its boxes alone would only fight the joints.
    variation(rock, location=(0.02, 0.02, 0.02), linear_velocity=(0.5, 0.1, 0.5), angular_velocity=(1.0, 1.0, 1.0))


# --- tower and bystanders -----------------------------------------------------------------------

def pinwheel_layer(mirrored):
    """16 blocks (centre x, y, rotated?) around a square ring, each side a run of BLOCKS_PER_SIDE
    blocks that covers one corner; `mirrored` turns the pinwheel the other way."""
    side = BLOCKS_PER_SIDE * BLOCK_LENGTH + BLOCK_DEPTH
    half = side / 2
    blocks = []
    for i in range(BLOCKS_PER_SIDE):
        t = -half + (i + 0.5) * BLOCK_LENGTH        # along a side, starting at its corner
        blocks += [(t, -half + BLOCK_DEPTH / 2, False),                 # south, from the west corner
                   (half - BLOCK_DEPTH / 2, t, True),                   # east, from the south corner
                   (-t, half - BLOCK_DEPTH / 2, False),                 # north, from the east corner
                   (-half + BLOCK_DEPTH / 2, -t, True)]                 # west, from the north corner
    if mirrored:
        blocks = [(-x, y, rotated) for x, y, rotated in blocks]
    return blocks


def build_tower(mats):
    """LAYERS x 16 = 192 blocks resting exactly on each other (no gaps, no overlaps) so the stack
    stands still until the rock arrives."""
    count = 0
    for layer in range(LAYERS):
        z = (layer + 0.5) * BLOCK_HEIGHT
        for x, y, rotated in pinwheel_layer(mirrored=layer % 2 == 1):
            count += 1
            size = (BLOCK_DEPTH, BLOCK_LENGTH, BLOCK_HEIGHT) if rotated else (BLOCK_LENGTH, BLOCK_DEPTH, BLOCK_HEIGHT)
            block = box(f"Block{count:03d}", size, location=TOWER_CENTRE + Vector((x, y, z)),
                        mat=mats["stone" if layer % 2 else "stone2"])
            rigid_body(block, "ACTIVE", "BOX", mass=BLOCK_MASS, friction=0.6, restitution=0.05)


def build_bystanders(mats):
    """Passive figures near the tower: a query asks for worlds where no block touches them."""
    for i, (x, y) in enumerate(BYSTANDERS):
        person = capsule(f"Bystander{i + 1}", 0.25, 1.7, location=(x, y, 0.85), mat=mats["bystander"])
        rigid_body(person, "PASSIVE", "CAPSULE", friction=0.5)


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "trebuchet_tower"
    scene_settings(duration_s=0.0)
    mats = {k: material(k, rgb) for k, rgb in {
        "ground": (0.3, 0.42, 0.25), "wood": (0.45, 0.3, 0.18), "rock": (0.3, 0.3, 0.32), "iron": (0.2, 0.2, 0.22),
        "stone": (0.75, 0.72, 0.65), "stone2": (0.68, 0.64, 0.58), "bystander": (0.9, 0.3, 0.2)}.items()}
    ground = box("Ground", (50, 30, 0.2), location=(8, 0, -0.1), mat=mats["ground"])
    rigid_body(ground, "PASSIVE", "BOX", friction=0.8)
    build_frame(mats)
    build_arm(mats)
    build_tower(mats)
    build_bystanders(mats)
    camera_and_lights(location=(6.0, -22.0, 7.5), target=(6.5, 0.0, 2.8), lens=30)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
