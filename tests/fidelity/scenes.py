"""Fidelity scenes: each function builds one small rigid-body scene in the current Blender file
the way an animator would, only with Blender's own operators and bundled add-ons (Add > Mesh,
Object > Rigid Body > Add Active / Passive, Change Shape, Calculate Mass, Copy from Active,
Connect, Cell Fracture), typed-in settings and keyframes. Nothing is set on the add-on's side.

Every scene starts from an empty factory file, simulates a few seconds at Blender's defaults
(24 fps, 10 substeps, 10 solver iterations) and is deterministic: Cell Fracture's random noise
is seeded. `SCENES` maps a scene name to (builder, one line on what Blender does with it).
"""
import math
import random

import addon_utils
import bpy

from many_worlds import compat

FPS = 24


# --- what an animator clicks ---------------------------------------------------------------

def select(objects, active=None):
    """Select exactly `objects`, with `active` (default: the first) active."""
    bpy.ops.object.select_all(action="DESELECT")
    for ob in objects:
        ob.select_set(True)
    bpy.context.view_layer.objects.active = active or objects[0]


def add_mesh(primitive, name, **kwargs):
    """Add > Mesh > <primitive> with the operator's own options (location, rotation, scale, size...)."""
    getattr(bpy.ops.mesh, f"primitive_{primitive}_add")(**kwargs)
    ob = bpy.context.active_object
    ob.name = name
    return ob


def add_rigid(objects, body_type="ACTIVE", shape=None):
    """Object > Rigid Body > Add Active/Passive on `objects`, then Change Shape if asked."""
    select(objects)
    bpy.ops.rigidbody.objects_add(type=body_type)
    if shape is not None:
        bpy.ops.rigidbody.shape_change(type=shape)
    return objects


def ground(shape, size=12.0, location=(0, 0, 0), name="Ground"):
    """A plane (Add > Mesh > Plane) made a passive rigid body, its shape changed to `shape`
    (None keeps Blender's default for a new rigid body)."""
    plane = add_mesh("plane", name, size=size, location=location)
    add_rigid([plane], "PASSIVE", shape)
    return plane


def connect(objects, active, con_type, pattern="SELECTED_TO_ACTIVE", pivot="CENTER"):
    """Object > Rigid Body > Connect; returns the constraint objects it made."""
    before = set(bpy.data.objects)
    select(objects, active)
    bpy.ops.rigidbody.connect(con_type=con_type, pivot_type=pivot, connection_pattern=pattern)
    made = [ob for ob in bpy.data.objects if ob not in before]
    return sorted(made, key=lambda ob: ob.name)


def key_throw(ob, velocity, release_frame, start_frame=1):
    """The usual throw: "Animated" keyed on from `start_frame` and the location keyed moving at
    `velocity` (m/s, linear keys), then "Animated" keyed off at `release_frame`."""
    rbo = ob.rigid_body
    start = ob.location.copy()
    last_keyed = release_frame - 1
    for frame, animated in ((start_frame, True), (last_keyed, True), (release_frame, False)):
        t = (min(frame, last_keyed) - start_frame) / FPS
        ob.location = [start[k] + velocity[k] * t for k in range(3)]
        ob.keyframe_insert("location", frame=frame)
        rbo.kinematic = animated
        ob.keyframe_insert("rigid_body.kinematic", frame=frame)
    # Graph Editor > Key > Interpolation Mode > Linear, so the ball leaves at its keyed speed.
    for curve in compat.object_fcurves(ob):
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"
    ob.location = start


def lock(rbc, kind, axes):
    """Limits of a constraint's `kind` ("lin" or "ang") axes checked and set to 0..0 (locked)."""
    for axis in axes:
        setattr(rbc, f"use_limit_{kind}_{axis}", True)
        setattr(rbc, f"limit_{kind}_{axis}_lower", 0.0)
        setattr(rbc, f"limit_{kind}_{axis}_upper", 0.0)


def frames(end, start=1):
    """Output frame range and Rigid Body World > Cache range, as both must be set by hand."""
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = start, end
    cache = scene.rigidbody_world.point_cache
    cache.frame_start, cache.frame_end = start, end
    scene.frame_set(start)


# --- scenes --------------------------------------------------------------------------------

def drop_on_box_plane():
    """Three cubes dropped on a plane with a BOX shape: a default cube (convex hull), one made
    BOX, one tilted onto an edge so it topples."""
    ground("BOX")
    plain = add_mesh("cube", "HullCube", size=0.5, location=(-1.5, 0, 1.0))
    boxed = add_mesh("cube", "BoxCube", size=0.5, location=(0, 0, 1.0), rotation=(0, 0, math.radians(30)))
    tilted = add_mesh("cube", "TiltedCube", size=0.4, location=(1.5, 0, 0.8),
                      rotation=(math.radians(25), math.radians(10), 0))
    add_rigid([plain, tilted])
    add_rigid([boxed], shape="BOX")
    frames(60)


def shapes_on_mesh_plane():
    """Every primitive shape dropped on a plane with a MESH shape (thickened by its 0.04 m margin)."""
    ground("MESH")
    ball = add_mesh("uv_sphere", "Ball", radius=0.25, location=(-2, 0, 1.0))
    drum = add_mesh("cylinder", "Drum", radius=0.25, depth=0.5, location=(-1, 0, 1.0))
    cone = add_mesh("cone", "Cone", radius1=0.3, depth=0.5, location=(0, 0, 1.0))
    pill = add_mesh("cylinder", "Pill", radius=0.15, depth=0.6, location=(1, 0, 1.0),
                    rotation=(math.radians(90), 0, 0))
    rock = add_mesh("ico_sphere", "Rock", radius=0.25, subdivisions=1, location=(2, 0, 1.0))
    monkey = add_mesh("monkey", "Suzanne", size=0.5, location=(3, 0, 1.0))
    add_rigid([ball], shape="SPHERE")
    add_rigid([drum], shape="CYLINDER")
    add_rigid([cone], shape="CONE")
    add_rigid([pill], shape="CAPSULE")
    add_rigid([rock, monkey])
    frames(72)


def drop_on_default_plane():
    """The plane as Blender makes it passive (its default shape, a convex hull of a flat mesh),
    with two cubes dropped on it."""
    ground(None)
    a = add_mesh("cube", "CubeA", size=0.4, location=(-0.5, 0, 1.0))
    b = add_mesh("cube", "CubeB", size=0.3, location=(0.5, 0, 0.6), rotation=(0, 0, math.radians(45)))
    add_rigid([a, b])
    frames(48)


def default_hulls():
    """Round things left at the default shape (Convex Hull): a cylinder on its side drops onto a
    passive step, a cylinder stands on the ground; the step is an octagonal slab moved in Edit Mode
    away from its origin, which stays at the world's origin, off its surface. (A UV sphere dropped
    straight down lands on its pole: Bullet's rounded margin rolls it off, ODE's point balances.)"""
    ground("BOX")
    step = add_mesh("cylinder", "Step", vertices=8, radius=1.0, depth=0.2, location=(0, 0, 0))
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.transform.translate(value=(-1.0, 2.0, 0.1))
    bpy.ops.object.mode_set(mode="OBJECT")
    add_rigid([step], "PASSIVE")
    barrel = add_mesh("cylinder", "Barrel", radius=0.15, depth=0.5, location=(-0.6, 2.0, 0.6),
                      rotation=(math.radians(90), 0, 0))
    post = add_mesh("cylinder", "Post", radius=0.2, depth=0.6, location=(1.0, 0, 0.8))
    add_rigid([barrel, post])
    frames(96)


def stacks_copy_settings():
    """A tower of five boxes set up once (BOX, friction 0.8) and copied to the others with Copy
    from Active, masses from Calculate Mass (Timber); beside it a 3-2-1 pyramid of default cubes."""
    ground("BOX")
    tower = [add_mesh("cube", f"Tower{k}", size=0.4, location=(-1, 0, 0.2 + 0.4 * k)) for k in range(5)]
    add_rigid(tower[:1], shape="BOX")
    tower[0].rigid_body.friction = 0.8
    select(tower, tower[0])
    bpy.ops.rigidbody.object_settings_copy()
    bpy.ops.rigidbody.mass_calculate(material="Timber")
    pyramid = []
    for row, count in enumerate((3, 2, 1)):
        for k in range(count):
            x = 1.0 + 0.42 * (k - (count - 1) / 2)
            pyramid.append(add_mesh("cube", f"Pyramid{row}{k}", size=0.4, location=(x, 0, 0.2 + 0.4 * row)))
    add_rigid(pyramid)
    frames(72)


def ramp_friction():
    """A passive box tilted 25° as a ramp; a slippery box (friction 0.1) slides down it, a grippy
    one (friction 1.0) stays; a MESH plane below catches the slider."""
    ground("MESH")
    ramp = add_mesh("cube", "Ramp", size=1.0, location=(0, 0, 0.6), rotation=(0, math.radians(25), 0),
                    scale=(2.0, 1.5, 0.1))
    add_rigid([ramp], "PASSIVE", "BOX")
    tilt = math.radians(25)
    for name, y, friction in (("Slippery", -0.4, 0.1), ("Grippy", 0.4, 1.0)):
        # On the ramp's top face, upslope.
        along, up = -0.5, 0.05 + 0.15 + 0.01
        x = along * math.cos(tilt) + up * math.sin(tilt)
        z = 0.6 - along * math.sin(tilt) + up * math.cos(tilt)
        box = add_mesh("cube", name, size=0.3, location=(x, y, z), rotation=(0, tilt, 0))
        add_rigid([box], shape="BOX")
        box.rigid_body.friction = friction
    frames(72)


def bouncy_balls():
    """Balls of bounciness 0, 0.5 and 0.9 dropped from 1.5 m on a bouncy (1.0) BOX plane."""
    plane = ground("BOX")
    plane.rigid_body.restitution = 1.0
    for k, bounce in enumerate((0.0, 0.5, 0.9)):
        ball = add_mesh("uv_sphere", f"Bounce{int(bounce * 10)}", radius=0.2, location=(k - 1.0, 0, 1.5))
        add_rigid([ball], shape="SPHERE")
        ball.rigid_body.restitution = bounce
    frames(96)


def thrown_with_damping():
    """Three cubes thrown sideways by keyed Animated (on for the first 6 frames), linear and
    angular damping 0, 0.5 and 0.9, landing and tumbling to rest on a MESH plane."""
    ground("MESH")
    for k, damping in enumerate((0.0, 0.5, 0.9)):
        cube = add_mesh("cube", f"Thrown{int(damping * 10)}", size=0.3, location=(-2.0, 1.0 * (k - 1), 1.2))
        add_rigid([cube])
        cube.rigid_body.linear_damping = damping
        cube.rigid_body.angular_damping = damping
        key_throw(cube, (3.0, 0.0, 1.0), release_frame=7)
    frames(84)


def start_deactivated():
    """Four boxes in a row left floating with Start Deactivated (and Enable Deactivation); a ball
    thrown by keyed Animated wakes the first and they knock each other down; a fifth sleeper out
    of reach stays in the air. A box without deactivation falls at once."""
    ground("BOX")
    sleepers = [add_mesh("cube", f"Sleeper{k}", size=0.3, location=(0.6 * k, 0, 1.2)) for k in range(4)]
    sleepers.append(add_mesh("cube", "SleeperFar", size=0.3, location=(0, -1.5, 1.2)))
    add_rigid(sleepers[:1])
    sleepers[0].rigid_body.use_deactivation = True
    sleepers[0].rigid_body.use_start_deactivated = True
    select(sleepers, sleepers[0])
    bpy.ops.rigidbody.object_settings_copy()
    awake = add_mesh("cube", "Awake", size=0.3, location=(-1.0, 1.0, 1.2))
    add_rigid([awake])
    ball = add_mesh("uv_sphere", "Ball", radius=0.15, location=(-1.5, 0, 1.2))
    add_rigid([ball], shape="SPHERE")
    ball.rigid_body.mass = 2.0
    key_throw(ball, (5.0, 0.0, 0.0), release_frame=5)
    frames(60)


def collision_collections():
    """Collision collections: a box in collection 2 falls through a box in collection 1 and both
    land on the ground (in 1 and 2); two boxes in collection 1 stack; a box only in collection 3
    falls through the ground."""
    plane = ground("BOX")
    plane.rigid_body.collision_collections[1] = True
    lower = add_mesh("cube", "Lower1", size=0.4, location=(-1, 0, 0.3))
    upper = add_mesh("cube", "Upper2", size=0.4, location=(-1, 0, 1.2))
    base = add_mesh("cube", "Base1", size=0.4, location=(0.5, 0, 0.3))
    top = add_mesh("cube", "Top1", size=0.4, location=(0.5, 0, 1.2))
    ghost = add_mesh("cube", "Ghost3", size=0.4, location=(2, 0, 0.6))
    add_rigid([lower, upper, base, top, ghost], shape="BOX")
    for ob, layer in ((upper, 1), (ghost, 2)):
        ob.rigid_body.collision_collections[layer] = True
        ob.rigid_body.collision_collections[0] = False
    frames(48)


def connect_each_type():
    """One passive post per constraint type with a bar hung from it by Object > Rigid Body >
    Connect (pivot at the post, at the bar for rails), the constraint empty rotated where the type's axis needs it:
    FIXED holds the bar level, POINT and HINGE swing it down, SLIDER and PISTON let it slide
    down a 45° rail to their limit, GENERIC (linear locked, angular ±30°) droops to its limit,
    GENERIC_SPRING (linear locked, angular springs) sags and settles."""
    setups = (("FIXED", None), ("POINT", None), ("HINGE", (math.radians(90), 0, 0)),
              ("SLIDER", (0, math.radians(45), 0)), ("PISTON", (0, math.radians(45), 0)),
              ("GENERIC", None), ("GENERIC_SPRING", None))
    for k, (kind, rotation) in enumerate(setups):
        y = 1.2 * k
        name = kind.title().replace("_", "")
        post = add_mesh("cube", f"Post{name}", size=0.2, location=(0, y, 2.0))
        bar = add_mesh("cube", f"Bar{name}", size=1.0, location=(0.5, y, 2.0), scale=(0.5, 0.08, 0.08))
        add_rigid([post], "PASSIVE", "BOX")
        add_rigid([bar], shape="BOX")
        # Rails run through the bar's centre (pivot at the bar), other joints sit at the post.
        pivot = "SELECTED" if kind in {"SLIDER", "PISTON"} else "ACTIVE"
        (con,) = connect([post, bar], post, kind, pivot=pivot)
        con.name = f"Joint{name}"
        if rotation is not None:
            con.rotation_euler = rotation
        rbc = con.rigid_body_constraint
        if kind in {"SLIDER", "PISTON"}:
            rbc.use_limit_lin_x = True
            rbc.limit_lin_x_lower, rbc.limit_lin_x_upper = 0.0, 0.6
        if kind in {"GENERIC", "GENERIC_SPRING"}:
            lock(rbc, "lin", "xyz")
        if kind == "GENERIC":
            for axis in "xyz":
                setattr(rbc, f"use_limit_ang_{axis}", True)
                setattr(rbc, f"limit_ang_{axis}_lower", math.radians(-30))
                setattr(rbc, f"limit_ang_{axis}_upper", math.radians(30))
        if kind == "GENERIC_SPRING":
            for axis in "xyz":
                setattr(rbc, f"use_spring_ang_{axis}", True)
                setattr(rbc, f"spring_stiffness_ang_{axis}", 40.0)
                setattr(rbc, f"spring_damping_ang_{axis}", 0.5)
    ground("BOX", location=(0, 3.6, 0), size=14)
    frames(72)


def springs():
    """GENERIC_SPRING as animators use it: a box on a spring under a passive beam (Z free, linear
    spring on Z) bobs and settles; a lid on angular springs (linear locked) sags and settles."""
    ground("BOX")
    beam = add_mesh("cube", "Beam", size=0.2, location=(0, 0, 2.5))
    bob = add_mesh("cube", "Bob", size=0.3, location=(0, 0, 1.8))
    hinge_post = add_mesh("cube", "LidPost", size=0.2, location=(2, 0, 1.0))
    lid = add_mesh("cube", "Lid", size=1.0, location=(2.5, 0, 1.0), scale=(0.5, 0.3, 0.03))
    add_rigid([beam, hinge_post], "PASSIVE", "BOX")
    add_rigid([bob, lid], shape="BOX")
    (hang,) = connect([beam, bob], beam, "GENERIC_SPRING", pivot="ACTIVE")
    hang.name = "Hang"
    rbc = hang.rigid_body_constraint
    lock(rbc, "lin", "xy")
    lock(rbc, "ang", "xyz")
    rbc.use_spring_z = True
    rbc.spring_stiffness_z, rbc.spring_damping_z = 60.0, 0.5
    (lid_joint,) = connect([hinge_post, lid], hinge_post, "GENERIC_SPRING", pivot="ACTIVE")
    lid_joint.name = "LidSpring"
    rbc = lid_joint.rigid_body_constraint
    lock(rbc, "lin", "xyz")
    for axis in "xyz":
        setattr(rbc, f"use_spring_ang_{axis}", True)
        setattr(rbc, f"spring_stiffness_ang_{axis}", 25.0)
        setattr(rbc, f"spring_damping_ang_{axis}", 0.5)
    frames(96)


def motor_paddle():
    """A paddle on a passive axle, hinged (HINGE) and driven (MOTOR, 4 rad/s, max impulse 2)
    about the same horizontal axis, knocking a box on the ground away as it comes round."""
    ground("BOX")
    axle = add_mesh("cube", "Axle", size=0.2, location=(0, 0, 0.75))
    paddle = add_mesh("cube", "Paddle", size=1.0, location=(0, 0, 1.2), scale=(0.06, 0.3, 0.4))
    box = add_mesh("cube", "Box", size=0.3, location=(0.35, 0, 0.16))
    add_rigid([axle], "PASSIVE", "BOX")
    add_rigid([paddle, box], shape="BOX")
    (hinge,) = connect([axle, paddle], axle, "HINGE", pivot="ACTIVE")
    hinge.name = "PaddleHinge"
    hinge.rotation_euler = (math.radians(90), 0, 0)  # hinge axis (its Z) along world Y
    (motor,) = connect([axle, paddle], axle, "MOTOR", pivot="ACTIVE")
    motor.name = "PaddleMotor"
    motor.rotation_euler = (0, 0, math.radians(90))  # motor axis (its X) along world Y
    rbc = motor.rigid_body_constraint
    rbc.use_motor_ang = True
    rbc.motor_ang_target_velocity, rbc.motor_ang_max_impulse = 4.0, 2.0
    frames(72)


def breakable_shelves():
    """Two shelves FIXED (breakable) to passive wall posts; a 10 kg box dropped on each: the weak
    joint (threshold 2) breaks and the shelf falls, the strong one (threshold 1000) holds."""
    ground("BOX")
    for k, (name, threshold) in enumerate((("Weak", 2.0), ("Strong", 1000.0))):
        y = 2.0 * k
        post = add_mesh("cube", f"Wall{name}", size=1.0, location=(0, y, 1.0), scale=(0.1, 0.5, 1.0))
        shelf = add_mesh("cube", f"Shelf{name}", size=1.0, location=(0.45, y, 1.2), scale=(0.8, 0.4, 0.06))
        load = add_mesh("cube", f"Load{name}", size=0.3, location=(0.6, y, 2.0))
        add_rigid([post], "PASSIVE", "BOX")
        add_rigid([shelf, load], shape="BOX")
        load.rigid_body.mass = 10.0
        (joint,) = connect([post, shelf], post, "FIXED")
        joint.name = f"Bracket{name}"
        joint.rigid_body_constraint.use_breaking = True
        joint.rigid_body_constraint.breaking_threshold = threshold
    frames(60)


def fracture_wall(lift=0.0, ground_shape="BOX"):
    """A wall cut by Cell Fracture (points from a child grid) into 15 convex pieces, masses by
    Calculate Mass (Brick (Common)), each piece joined to its neighbours by Connect FIXED (breakable,
    threshold 20), standing on a passive plane; a timber ball (Calculate Mass) thrown by keyed
    Animated knocks a hole in it."""
    addon_utils.enable("object_fracture_cell", default_set=False)
    ground(ground_shape, size=20)
    z = 0.6 + lift
    wall = add_mesh("cube", "Wall", size=1.0, location=(0, 0, z), scale=(2.0, 0.2, 1.2))
    grid = add_mesh("grid", "Cuts", x_subdivisions=4, y_subdivisions=2, size=1.0,
                    location=(0, 0, z), rotation=(math.radians(90), 0, 0), scale=(1.6, 0.9, 1.0))
    grid.parent = wall
    grid.matrix_parent_inverse = wall.matrix_world.inverted()
    select([wall])
    random.seed(7)  # Cell Fracture jitters cell points with Python's random
    bpy.ops.object.add_fracture_cell_objects(source={"VERT_CHILD"}, source_limit=0, use_debug_redraw=False,
                                             use_recenter=True, use_remove_original=True)
    pieces = sorted(bpy.context.selected_objects, key=lambda ob: ob.name)
    select([grid])
    bpy.ops.object.delete()
    add_rigid(pieces)
    bpy.ops.rigidbody.mass_calculate(material="Brick (Common)")
    joints = []
    for i, piece in enumerate(pieces):
        # Neighbours: pieces whose bounds overlap this one's grown by 1 cm.
        near = [other for other in pieces[i + 1:] if _touching(piece, other, 0.01)]
        if near:
            joints += connect([piece, *near], piece, "FIXED")
    for joint in joints:
        joint.rigid_body_constraint.use_breaking = True
        joint.rigid_body_constraint.breaking_threshold = 20.0
    ball = add_mesh("uv_sphere", "Ball", radius=0.25, location=(0.2, -3.0, 0.9))
    add_rigid([ball], shape="SPHERE")
    bpy.ops.rigidbody.mass_calculate(material="Timber")
    key_throw(ball, (0.0, 8.0, 0.0), release_frame=5)
    frames(72)


def fracture_wall_lifted():
    """The same wall modelled 5 mm above the plane (it settles onto it in the first frames)."""
    fracture_wall(lift=0.005)


def _touching(a, b, gap):
    """Whether the world bounding boxes of a and b overlap once grown by `gap` (m)."""
    from mathutils import Vector

    def bounds(ob):
        corners = [ob.matrix_world @ Vector(c) for c in ob.bound_box]
        return [min(c[k] for c in corners) for k in range(3)], [max(c[k] for c in corners) for k in range(3)]
    (alo, ahi), (blo, bhi) = bounds(a), bounds(b)
    return all(alo[k] - gap <= bhi[k] and blo[k] - gap <= ahi[k] for k in range(3))


SCENES = {
    "drop_on_box_plane": (drop_on_box_plane, "cubes (hull, BOX, tilted) drop on a BOX plane and rest"),
    "shapes_on_mesh_plane": (shapes_on_mesh_plane, "sphere, cylinder, cone, capsule, hulls drop on a MESH plane"),
    "drop_on_default_plane": (drop_on_default_plane, "cubes drop on a plane with its default CONVEX_HULL shape"),
    "default_hulls": (default_hulls, "a lying cylinder (a default hull) drops onto a step whose origin is off its "
                                     "surface; a cylinder stands"),
    "stacks_copy_settings": (stacks_copy_settings, "a tower (Copy from Active, Calculate Mass) and a pyramid stand"),
    "ramp_friction": (ramp_friction, "friction 0.1 slides down a 25° ramp, friction 1.0 stays"),
    "bouncy_balls": (bouncy_balls, "balls of bounciness 0, 0.5, 0.9 bounce on a bouncy plane"),
    "thrown_with_damping": (thrown_with_damping, "keyed-Animated throws with damping 0, 0.5, 0.9 land and rest"),
    "start_deactivated": (start_deactivated, "Start Deactivated boxes float until knocked; one out of reach stays up"),
    "collision_collections": (collision_collections, "boxes in other collision collections pass through"),
    "connect_each_type": (connect_each_type, "Connect with each constraint type hangs a bar from a post"),
    "springs": (springs, "GENERIC_SPRING: a box bobs on a linear spring, a lid sags on angular springs"),
    "motor_paddle": (motor_paddle, "a HINGE + MOTOR paddle comes round and knocks a box away"),
    "breakable_shelves": (breakable_shelves, "a dropped load breaks a weak FIXED shelf, not a strong one"),
    "fracture_wall": (fracture_wall, "a thrown ball knocks a hole in a Cell Fracture wall (breakable FIXED)"),
    "fracture_wall_lifted": (fracture_wall_lifted, "the same wall modelled 5 mm above the plane"),
}
