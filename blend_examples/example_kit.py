"""Helpers the example build scripts share: meshes made from nothing, Blender rigid bodies and
constraints set up the way the engine reads them, variation ranges, camera and lights, and the
scene's rigid-body world. Each build script puts this folder on sys.path and imports from here."""
import math
import os
import sys

import bmesh
import bpy
from mathutils import Euler, Matrix, Vector

# Objects thinner than this get a small explicit collision margin: Blender's default 4 cm would
# make thin boards and small marbles collide at the wrong distance.
THIN_OBJECT, THIN_MARGIN = 0.1, 0.0005   # metres
ALL_COLLECTIONS = range(20)


def output_path():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(argv) != 1:
        sys.exit(f"usage: blender -b --factory-startup --python {os.path.basename(sys.argv[-1])} -- OUTPUT.blend")
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


def rigid_body(obj, body_type, shape, mass=1.0, friction=0.5, restitution=0.0, damping=(0.04, 0.1),
               collections=ALL_COLLECTIONS):
    bpy.context.view_layer.objects.active = obj
    bpy.ops.rigidbody.object_add(type=body_type)
    rb = obj.rigid_body
    rb.collision_shape, rb.mass, rb.friction, rb.restitution = shape, mass, friction, restitution
    rb.linear_damping, rb.angular_damping = damping
    # While use_margin is off Blender uses a hidden 4 cm margin: inside BOX and CYLINDER shapes, which
    # breaks those thinner than 8 cm, and outside CONE shapes. Such objects get a tiny explicit
    # margin instead (the engine adds an explicit margin outside every shape; 0.5 mm is harmless
    # there). Everything else keeps the default, which the engine ignores; a Convex Hull at the
    # default collides with its own points, as Bullet shrinks it by the margin it adds.
    if shape == "CONE" or smallest_extent(obj) < THIN_OBJECT:
        rb.use_margin, rb.collision_margin = True, THIN_MARGIN
    rb.collision_collections = [i in collections for i in range(20)]
    return rb


def compound(name, parts, location, rotation=(0, 0, 0), mat=None, mass=1.0, **rigid):
    """An ACTIVE COMPOUND body made of boxes; returns (parent, centroid). `parts` are (size, offset)
    or (size, offset, euler) in the body's frame with `location` as reference point. The parent carries the visible mesh; each part is a child
    with its own BOX rigid body (how Blender builds compounds), drawn as wire and not rendered.
    The origin goes to the volume centroid of the parts: Blender puts the centre of mass at the
    origin, the engine computes it from the shapes, and this way both agree."""
    parts = [(p[0], p[1], p[2] if len(p) > 2 else (0, 0, 0)) for p in parts]
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


def variation(obj, location=(0, 0, 0), rotation=(0, 0, 0), linear_velocity=(0, 0, 0), angular_velocity=(0, 0, 0),
              linear_velocity_range=None):
    """Symmetric ranges [-r, +r] per axis, world frame, added to the object's initial state;
    `linear_velocity_range` = (low, high) instead gives a velocity range not centred on zero (a
    throw, a shove)."""
    ranges = {}
    for key, r in (("location", location), ("rotation", rotation),
                   ("linear_velocity", linear_velocity), ("angular_velocity", angular_velocity)):
        ranges[f"{key}_min"], ranges[f"{key}_max"] = [-v for v in r], list(r)
    if linear_velocity_range is not None:
        ranges["linear_velocity_min"], ranges["linear_velocity_max"] = (list(v) for v in linear_velocity_range)
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


def scene_settings(fps, frame_start, frame_end, substeps, solver_iterations, world_count, seed, duration_s=0.0):
    """The Rigid Body World and the frame range, and the add-on's sampling settings (Scene.mwb,
    written as an ID property group so no add-on is needed to build the file)."""
    scene = bpy.context.scene
    scene.render.fps = fps
    scene.frame_start, scene.frame_end = frame_start, frame_end
    bpy.ops.rigidbody.world_add()
    rbw = scene.rigidbody_world
    rbw.substeps_per_frame, rbw.solver_iterations = substeps, solver_iterations
    rbw.point_cache.frame_start, rbw.point_cache.frame_end = frame_start, frame_end
    scene["mwb"] = {"world_count": world_count, "seed": seed, "duration_s": duration_s}
