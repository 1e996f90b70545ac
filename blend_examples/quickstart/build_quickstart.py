"""Builds the quick-start example: five toys wait behind an animated gate, then tumble down a chute
past a splitter peg into three bins.

Goal: "the marble lands in the left bin". Small on purpose, so it samples in seconds.

Run:  blender -b --factory-startup --python blend_examples/quickstart/build_quickstart.py -- OUT.blend
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
FRAME_START, FRAME_END = 1, 96          # 4 s: everything has settled in the bins by then
SUBSTEPS, SOLVER_ITERATIONS = 10, 10    # 240 Hz, what the engine steps at too
THIN_OBJECT, THIN_MARGIN = 0.1, 0.0005   # metres; see rigid_body()
WORLD_COUNT, SEED = 200, 1

CHUTE_LENGTH, CHUTE_WIDTH, CHUTE_TILT = 3.0, 1.2, math.radians(25)
CHUTE_LOW_END = Vector((0.0, -1.1, 0.55))   # lower edge centre of the chute floor, just behind the bins
GATE_FROM_TOP, GATE_LIFT = 0.9, 0.5
GATE_OPEN_FRAMES = (10, 18)                 # the gate rises between these frames
BIN_WIDTH, BIN_DEPTH, BIN_WALL_HEIGHT = 0.6, 1.0, 0.3
BIN_NAMES = ("Left", "Middle", "Right")     # as seen from the camera (-X is left)
WALL_THICKNESS = 0.05


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


def cone(name, radius, depth, **kw):
    return mesh_object(name, lambda bm: bmesh.ops.create_cone(
        bm, cap_ends=True, segments=32, radius1=radius, radius2=0.0, depth=depth), **kw)


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

def build_ground(mats):
    ground = box("Ground", (8, 8, 0.2), location=(0, 0, -0.1), mat=mats["floor"])
    rigid_body(ground, "PASSIVE", "BOX", friction=0.6)


def build_chute(mats):
    """A tilted floor with rails, descending towards the camera (-Y); a splitter peg near the
    bottom sends things left or right, which is what makes the outcome worth sampling."""
    down = Vector((0, -math.cos(CHUTE_TILT), -math.sin(CHUTE_TILT)))   # along the chute, downhill
    normal = Vector((0, -math.sin(CHUTE_TILT), math.cos(CHUTE_TILT)))
    centre = CHUTE_LOW_END - down * (CHUTE_LENGTH / 2) - normal * WALL_THICKNESS / 2
    tilt = (CHUTE_TILT, 0, 0)
    floor = box("Chute", (CHUTE_WIDTH, CHUTE_LENGTH, WALL_THICKNESS), location=centre, rotation=tilt, mat=mats["chute"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.4)
    for side, sign in (("L", -1), ("R", 1)):
        rail_centre = centre + Vector((sign * (CHUTE_WIDTH + WALL_THICKNESS) / 2, 0, 0)) + normal * 0.1
        rail = box(f"ChuteRail{side}", (WALL_THICKNESS, CHUTE_LENGTH, 0.25), location=rail_centre, rotation=tilt,
                   mat=mats["chute"])
        rigid_body(rail, "PASSIVE", "BOX", friction=0.3)
    peg_centre = CHUTE_LOW_END - down * 0.45 + normal * 0.15
    peg = cylinder("SplitterPeg", 0.07, 0.5, location=peg_centre, rotation=tilt, mat=mats["peg"])
    rigid_body(peg, "PASSIVE", "CYLINDER", restitution=0.3)


def build_gate(mats):
    """An animated passive gate across the chute: it holds the toys while they settle against it,
    then lifts (keyframed, Blender's "Animated" rigid body), so every world starts from a jumble."""
    along = Vector((0, -math.cos(CHUTE_TILT), -math.sin(CHUTE_TILT)))
    normal = Vector((0, -math.sin(CHUTE_TILT), math.cos(CHUTE_TILT)))
    top_edge = CHUTE_LOW_END - along * CHUTE_LENGTH
    closed = top_edge + along * GATE_FROM_TOP + normal * 0.16
    gate = box("Gate", (CHUTE_WIDTH, WALL_THICKNESS, 0.3), location=closed, rotation=(CHUTE_TILT, 0, 0),
               mat=mats["peg"])
    rigid_body(gate, "PASSIVE", "BOX", friction=0.3)
    gate.rigid_body.kinematic = True
    for frame, lift in ((FRAME_START, 0.0), (GATE_OPEN_FRAMES[0], 0.0), (GATE_OPEN_FRAMES[1], GATE_LIFT)):
        gate.location = closed + Vector((0, 0, lift))
        gate.keyframe_insert("location", frame=frame)
    for fcurve in gate.animation_data.action.fcurves:
        for key in fcurve.keyframe_points:
            key.interpolation = "LINEAR"
    gate.location = closed


def build_bins(mats):
    """Three bins side by side in front of the chute's lower end; each has a coloured floor tile
    (BinLeftFloor, ...) so a screen box over one is easy to draw."""
    y_back, y_front = CHUTE_LOW_END.y - 0.05, CHUTE_LOW_END.y - 0.05 - BIN_DEPTH
    width = BIN_WIDTH * len(BIN_NAMES)
    y_mid = (y_back + y_front) / 2
    for i in range(len(BIN_NAMES) + 1):
        x = -width / 2 + i * BIN_WIDTH
        wall = box(f"BinDivider{i}", (WALL_THICKNESS, BIN_DEPTH, BIN_WALL_HEIGHT),
                   location=(x, y_mid, BIN_WALL_HEIGHT / 2), mat=mats["bin"])
        rigid_body(wall, "PASSIVE", "BOX")
    for name, y, height in (("BinBack", y_back, BIN_WALL_HEIGHT), ("BinFront", y_front, 2 * BIN_WALL_HEIGHT)):
        # the front wall is taller: things leave the chute fast and would fly over a low one
        wall = box(name, (width + WALL_THICKNESS, WALL_THICKNESS, height), location=(0, y, height / 2), mat=mats["bin"])
        rigid_body(wall, "PASSIVE", "BOX")
    for i, label in enumerate(BIN_NAMES):
        x = -width / 2 + (i + 0.5) * BIN_WIDTH
        tile = box(f"Bin{label}Floor", (BIN_WIDTH - WALL_THICKNESS, BIN_DEPTH - WALL_THICKNESS, 0.01),
                   location=(x, y_mid, 0.005), mat=mats[f"bin{label}"])
        rigid_body(tile, "PASSIVE", "BOX", friction=0.6)


def build_toys(mats):
    """Five active bodies, one of each primitive shape, at the top of the chute. The marble is the
    one the goal is about; the others get in its way."""
    up_chute = Vector((0, math.cos(CHUTE_TILT), math.sin(CHUTE_TILT)))
    top = CHUTE_LOW_END + up_chute * (CHUTE_LENGTH - 0.35) + Vector((0, 0, 0.2))
    # a centimetre off the chute's centre line: dead centre, it can balance on the splitter peg
    marble = sphere("Marble", 0.1, location=top + Vector((0.01, 0.0, 0.0)), mat=mats["marble"])
    rigid_body(marble, "ACTIVE", "SPHERE", mass=0.3, friction=0.3, restitution=0.5)
    variation(marble, location=(0.15, 0.03, 0.02), linear_velocity=(0.3, 0.1, 0.0))

    die = box("Die", (0.2, 0.2, 0.2), location=top + Vector((-0.35, -0.25, 0.05)), mat=mats["die"])
    rigid_body(die, "ACTIVE", "BOX", mass=0.5, friction=0.5, restitution=0.2)
    variation(die, location=(0.1, 0.1, 0.05), rotation=(0.3, 0.3, 0.3), angular_velocity=(4, 4, 4))

    cone_ = cone("Cone", 0.13, 0.3, location=top + Vector((0.35, -0.25, 0.05)), mat=mats["cone"])
    rigid_body(cone_, "ACTIVE", "CONE", mass=0.3, restitution=0.1)
    variation(cone_, location=(0.1, 0.1, 0.05), rotation=(0.3, 0.3, 0.3), angular_velocity=(3, 3, 3))

    can = cylinder("Can", 0.1, 0.3, location=top + Vector((-0.3, 0.2, 0.15)), rotation=(0, math.pi / 2, 0),
                   mat=mats["can"])
    rigid_body(can, "ACTIVE", "CYLINDER", mass=0.4, friction=0.4, restitution=0.1)
    variation(can, location=(0.05, 0.05, 0.05), rotation=(0.2, 0.2, 0.2), angular_velocity=(1, 1, 1))

    pill = capsule("Pill", 0.07, 0.3, location=top + Vector((0.3, 0.2, 0.15)), rotation=(math.pi / 2, 0, 0.4),
                   mat=mats["pill"])
    rigid_body(pill, "ACTIVE", "CAPSULE", mass=0.2, restitution=0.2)
    variation(pill, location=(0.05, 0.05, 0.05), rotation=(0.3, 0.3, 0.3), angular_velocity=(2, 2, 2))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "quickstart"
    scene_settings(duration_s=0.0)
    mats = {k: material(k, rgb) for k, rgb in {
        "floor": (0.5, 0.5, 0.5), "chute": (0.55, 0.4, 0.25), "peg": (0.8, 0.8, 0.8), "bin": (0.35, 0.35, 0.4),
        "binLeft": (0.2, 0.7, 0.25), "binMiddle": (0.75, 0.7, 0.2), "binRight": (0.7, 0.25, 0.2),
        "marble": (0.1, 0.3, 0.9), "die": (0.9, 0.9, 0.85), "cone": (0.95, 0.45, 0.1), "can": (0.7, 0.1, 0.1),
        "pill": (0.6, 0.2, 0.7)}.items()}
    build_ground(mats)
    build_chute(mats)
    build_gate(mats)
    build_bins(mats)
    build_toys(mats)
    camera_and_lights(location=(2.6, -6.6, 4.4), target=(0, -0.3, 0.6), lens=30)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
