"""Builds the trebuchet-and-tower example: a counterweight trebuchet throws a rock at a tower of
192 stacked blocks, with three bystanders standing around the tower.

Goals (queries in the paper): "the rock hits the tower" and "... the falling blocks miss the
bystanders".

Mechanism, the simplest that works: the arm (beam, counterweight and lip joined by FIXED
constraints) turns on a HINGE; the rock rests on the arm's leading face against the lip at its tip. When the falling
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
WORLD_COUNT, SEED = 300, 1
COLLISION_MARGIN = 0.005

# trebuchet, throwing along +X; the arm swings in the XZ plane about the Y axis
PIVOT = Vector((0.0, 0.0, 3.2))
LONG_ARM, SHORT_ARM, BEAM_SECTION = 4.0, 1.2, 0.15
COUNTERWEIGHT_SIZE, COUNTERWEIGHT_MASS = 0.9, 300.0
BEAM_MASS, LIP_MASS = 50.0, 2.0
COCKED_ANGLE = math.radians(225)        # long arm direction at the start, from +X towards +Z
RELEASE_ANGLE = math.radians(120)       # the hinge limit stops the arm here: a throw 30 degrees up
ROCK_RADIUS, ROCK_MASS = 0.18, 20.0
FRAME_HALF_GAP = 0.55                   # uprights either side of the arm, clear of the counterweight

# tower: 12 layers of 16 blocks in a pinwheel ring; alternate layers are mirrored so joints overlap
TOWER_CENTRE = Vector((11.0, 0.0, 0.0))        # the rock, thrown as built, meets the tower at about 2.7 m
LAYERS, BLOCKS_PER_SIDE = 12, 4
BLOCK_LENGTH, BLOCK_DEPTH, BLOCK_HEIGHT, BLOCK_MASS = 0.5, 0.25, 0.25, 5.0
BYSTANDERS = ((TOWER_CENTRE.x + 2.6, 0.9), (TOWER_CENTRE.x + 0.8, -2.3), (TOWER_CENTRE.x - 0.6, 2.4))   # within reach of falling blocks


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


def sphere(name, radius, **kw):
    return mesh_object(name, lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=32, v_segments=16, radius=radius), **kw)


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


def rigid_body(obj, body_type, shape, mass=1.0, friction=0.5, restitution=0.0, damping=(0.04, 0.1)):
    bpy.context.view_layer.objects.active = obj
    bpy.ops.rigidbody.object_add(type=body_type)
    rb = obj.rigid_body
    rb.collision_shape, rb.mass, rb.friction, rb.restitution = shape, mass, friction, restitution
    rb.linear_damping, rb.angular_damping = damping
    # explicit, so Blender and the engine read the same margin (Blender's hidden default is 4 cm)
    rb.use_margin, rb.collision_margin = True, COLLISION_MARGIN
    return rb


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
    for key, r in (("location", location), ("rotation", rotation),
                   ("linear_velocity", linear_velocity), ("angular_velocity", angular_velocity)):
        obj[f"mwb_{key}_min"] = [-v for v in r]
        obj[f"mwb_{key}_max"] = list(r)


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
    scene["mwb_world_count"], scene["mwb_seed"], scene["mwb_duration_s"] = WORLD_COUNT, SEED, duration_s




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
    """Beam, counterweight and lip as three boxes joined by FIXED constraints (each box's own
    inertia is then exact in Blender and in the engine; a Blender COMPOUND takes its inertia from
    the bounding box), hinged to an upright; the hinge stops at RELEASE_ANGLE. The rock rests on the
    leading face against the lip."""
    half = BEAM_SECTION / 2
    rotation = arm_rotation()
    place = Matrix.Translation(PIVOT) @ Euler(rotation).to_matrix().to_4x4()
    beam = box("Arm", (LONG_ARM + SHORT_ARM, BEAM_SECTION, BEAM_SECTION),
               location=place @ Vector(((LONG_ARM - SHORT_ARM) / 2, 0, 0)), rotation=rotation, mat=mats["wood"])
    rigid_body(beam, "ACTIVE", "BOX", mass=BEAM_MASS, friction=0.6, damping=(0.0, 0.02))
    weight = box("Counterweight", (COUNTERWEIGHT_SIZE,) * 3, location=place @ Vector((-SHORT_ARM, 0, 0)),
                 rotation=rotation, mat=mats["iron"])
    rigid_body(weight, "ACTIVE", "BOX", mass=COUNTERWEIGHT_MASS, friction=0.6, damping=(0.0, 0.02))
    lip = box("Lip", (0.08, BEAM_SECTION, 0.35), location=place @ Vector((LONG_ARM + 0.04 - half, 0, -half - 0.175)),
              rotation=rotation, mat=mats["wood"])
    rigid_body(lip, "ACTIVE", "BOX", mass=LIP_MASS, friction=0.6)
    constraint("CounterweightFixed", "FIXED", beam, weight, location=weight.location)
    constraint("LipFixed", "FIXED", beam, lip, location=lip.location)
    # The hinge axis is the empty's local Z, here turned onto world -Y. Blender measures the angle of
    # object1 (upright) relative to object2 (beam), so about -Y that angle grows as the long arm swings
    # up and over (clockwise seen from the camera), and the upper limit is the release.
    constraint("ArmHinge", "HINGE", bpy.data.objects["UprightR"], beam, location=PIVOT, rotation=(math.pi / 2, 0, 0),
               use_limit_ang_z=True, limit_ang_z_lower=math.radians(-5),
               limit_ang_z_upper=COCKED_ANGLE - RELEASE_ANGLE)
    rock_at = place @ Vector((LONG_ARM - ROCK_RADIUS - 0.06 - half, 0, -half - ROCK_RADIUS - 0.002))
    rock = sphere("Rock", ROCK_RADIUS, location=rock_at, mat=mats["rock"])
    rigid_body(rock, "ACTIVE", "SPHERE", mass=ROCK_MASS, friction=0.6, restitution=0.1)
    # Only the rock varies: a nudge as it sits in the cup changes where it flies, which is what the
    # paper got by varying the release time; the jointed arm gets no variation, since moving one of
    # its boxes alone would only fight the joints.
    variation(rock, location=(0.02, 0.02, 0.02), linear_velocity=(0.5, 0.4, 0.5), angular_velocity=(1.0, 1.0, 1.0))


# --- tower and bystanders -----------------------------------------------------------------------

def pinwheel_layer(mirrored):
    """16 blocks (centre x, y, rotated?) around a square ring, each side a run of BLOCKS_PER_SIDE
    blocks that covers one corner; `mirrored` turns the pinwheel the other way."""
    side = BLOCKS_PER_SIDE * BLOCK_LENGTH + BLOCK_DEPTH
    half, run = side / 2, BLOCKS_PER_SIDE * BLOCK_LENGTH
    blocks = []
    for i in range(BLOCKS_PER_SIDE):
        t = -half + (i + 0.5) * BLOCK_LENGTH        # along a side, starting at its corner
        blocks += [(t, -half + BLOCK_DEPTH / 2, False),                 # south, from the west corner
                   (half - BLOCK_DEPTH / 2, t, True),                   # east, from the south corner
                   (-t, half - BLOCK_DEPTH / 2, False),                 # north, from the east corner
                   (-half + BLOCK_DEPTH / 2, -t, True)]                 # west, from the north corner
    assert abs(run + BLOCK_DEPTH - side) < 1e-9
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
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
