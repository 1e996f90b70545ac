"""Blender's rigid-body world, bodies and constraints -> scene JSON ("mwb-scene" v1).

Reads only Blender's own Rigid Body World / Rigid Body / Rigid Body Constraint settings plus the
add-on's per-object variation ranges. Shapes follow what Blender's Bullet integration builds from
the object's bounding box (quadrics stand on local Z) with the object's scale applied, so the
engine sees the same sizes the user sees. Whatever the engine cannot run is listed in `problems`
as "object: setting: reason" and never dropped silently.
"""
import json
from dataclasses import dataclass, field

from mathutils import Matrix

from . import _native, compat
from .props import upgrade_saved_variation

SCENE_FORMAT = "mwb-scene"
SCENE_VERSION = 1
# Scale components closer than this count as equal (uniform scale).
SCALE_TOLERANCE = 1e-5


@dataclass
class ExportResult:
    scene: dict = None
    problems: list = field(default_factory=list)

    def to_json(self):
        return json.dumps(self.scene, indent=1)


def _vec(v):
    return [float(x) for x in v]


def _transform(matrix):
    """(location, unit quaternion) of a world matrix, plus its scale (applied to shapes instead)."""
    location, rotation, scale = matrix.decompose()
    rotation.normalize()
    return {"location": _vec(location), "rotation": _vec(rotation)}, scale


def _half_size(ob):
    """Half the object-space bounding-box size, as Blender's rigid body code measures it."""
    corners = [c[:] for c in ob.bound_box]
    return [(max(c[k] for c in corners) - min(c[k] for c in corners)) / 2 for k in range(3)]


def _mesh_data(ob, rbo, depsgraph):
    """Object-space vertices and triangles of the mesh the rigid body uses (Blender's 'Source')."""
    if rbo.mesh_source == "BASE" or depsgraph is None:
        mesh = ob.data
        owner = None
    else:
        owner = ob.evaluated_get(depsgraph)
        mesh = owner.to_mesh()
    try:
        mesh.calc_loop_triangles()
        vertices = [c for v in mesh.vertices for c in v.co]
        triangles = [i for t in mesh.loop_triangles for i in t.vertices]
    finally:
        if owner is not None:
            owner.to_mesh_clear()
    return vertices, triangles


# Set by Bake World on the objects it keys (bake.hand_to_keys): they export as before the bake.
PREBAKE_MATRIX = "mwb_prebake_matrix"


def _prebake_matrix(ob):
    """The world matrix a baked object had before its first bake, or None if it is not baked."""
    flat = ob.get(PREBAKE_MATRIX)
    if flat is None or len(flat) != 16:
        return None
    from mathutils import Matrix
    return Matrix([list(flat[4 * r:4 * r + 4]) for r in range(4)])


def _keyed_animated(ob, frame_start, frame_end):
    """Per frame of the range, whether the object's keyed "Animated" (rigid_body.kinematic) is on;
    None when it is not keyed."""
    curve = compat.find_fcurve(ob, "rigid_body.kinematic", 0)
    if curve is None:
        return None
    return [curve.evaluate(frame) >= 0.5 for frame in range(frame_start, frame_end + 1)]


class SceneExporter:
    def __init__(self, scene, depsgraph=None):
        self.scene = scene
        self.depsgraph = depsgraph
        self.problems = []
        self.rbw = scene.rigidbody_world

    def report(self, name, setting, reason):
        self.problems.append(f"{name}: {setting}: {reason}")

    # --- shapes -----------------------------------------------------------------------------

    def _check_scale(self, ob, shape_type, scale):
        if any(s < 0 for s in scale) or scale.x * scale.y * scale.z < 0:
            self.report(ob.name, "scale", "negative (mirrored) scale is not supported; exported with its absolute value")
        s = [abs(c) for c in scale]
        if shape_type == "SPHERE" and max(s) - min(s) > SCALE_TOLERANCE:
            self.report(ob.name, "scale", "non-uniform scale on a SPHERE; the radius uses the largest scale")
        if shape_type in {"CAPSULE", "CYLINDER", "CONE"} and abs(s[0] - s[1]) > SCALE_TOLERANCE:
            self.report(ob.name, "scale", f"X and Y scale differ on a {shape_type}; the radius uses the larger one")

    def shape(self, ob, rbo, scale, simulated):
        """The shape dict of one object; None (reported) when it cannot be exported."""
        kind = rbo.collision_shape
        self._check_scale(ob, kind, scale)
        s = [abs(c) for c in scale]
        h = _half_size(ob)
        if kind == "BOX":
            return {"type": "BOX", "half_extents_m": [h[k] * s[k] for k in range(3)]}
        if kind == "SPHERE":
            return {"type": "SPHERE", "radius_m": max(h) * max(s)}
        if kind in {"CAPSULE", "CYLINDER", "CONE"}:
            radius = max(h[0], h[1]) * max(s[0], s[1])
            half_height = h[2] * s[2]
            if kind == "CAPSULE":
                # Blender's capsule: radius from X/Y, cylinder part 2 * (half Z - radius), so the
                # full length is the bounding box height unless the caps alone are taller.
                cylinder_half = max(0.0, h[2] - max(h[0], h[1])) * s[2]
                return {"type": "CAPSULE", "radius_m": radius, "height_m": 2 * (radius + cylinder_half)}
            return {"type": kind, "radius_m": radius, "height_m": 2 * half_height}
        if kind in {"CONVEX_HULL", "MESH"}:
            if ob.type != "MESH":
                self.report(ob.name, "collision_shape", f"{kind} needs a mesh object, this is a {ob.type}")
                return None
            if rbo.use_deform:
                self.report(ob.name, "use_deform", "deforming collision meshes are not supported; "
                                                   "the mesh at the start frame is used")
            vertices, triangles = _mesh_data(ob, rbo, self.depsgraph)
            vertices = [c * s[k % 3] for k, c in enumerate(vertices)]
            if kind == "MESH" and simulated:
                self.report(ob.name, "collision_shape", "MESH on an active body is not supported by the engine; "
                                                        "exported as CONVEX_HULL")
                kind = "CONVEX_HULL"
            if kind == "CONVEX_HULL":
                return {"type": "CONVEX_HULL", "vertices_m": vertices}
            return {"type": "MESH", "vertices_m": vertices, "triangles": triangles}
        if kind == "COMPOUND":
            return self.compound(ob, simulated)
        self.report(ob.name, "collision_shape", f"{kind} is not supported")
        return None

    def compound_children(self, ob):
        return [c for c in self.rbw.collection.objects
                if c.parent == ob and c.rigid_body is not None and c.rigid_body.collision_shape != "COMPOUND"]

    def compound(self, ob, simulated):
        # Blender builds a compound from the rigid-body children parented to the object, each at
        # its pose relative to the parent; scales are applied to the child shapes.
        children = []
        location, rotation, _ = ob.matrix_world.decompose()
        parent_inverse = (Matrix.Translation(location) @ rotation.to_matrix().to_4x4()).inverted()
        for child in self.compound_children(ob):
            offset, _ = _transform(parent_inverse @ child.matrix_world)
            _, child_scale = _transform(child.matrix_world)
            shape = self.shape(child, child.rigid_body, child_scale, simulated)
            if shape is not None:
                shape["offset"] = offset
                children.append(shape)
        if not children:
            self.report(ob.name, "collision_shape", "COMPOUND without rigid-body children parented to it")
            return None
        return {"type": "COMPOUND", "children": children}

    # --- bodies -----------------------------------------------------------------------------

    def variation(self, ob):
        upgrade_saved_variation(ob)
        v = ob.mwb_variation
        fields = {"location_min_m": v.location_min, "location_max_m": v.location_max,
                  "rotation_min_rad": v.rotation_min, "rotation_max_rad": v.rotation_max,
                  "linear_velocity_min": v.linear_velocity_min, "linear_velocity_max": v.linear_velocity_max,
                  "angular_velocity_min": v.angular_velocity_min, "angular_velocity_max": v.angular_velocity_max}
        out = {k: _vec(val) for k, val in fields.items() if any(val)}
        for low, high in (("location_min_m", "location_max_m"), ("rotation_min_rad", "rotation_max_rad"),
                          ("linear_velocity_min", "linear_velocity_max"),
                          ("angular_velocity_min", "angular_velocity_max")):
            lo, hi = fields[low], fields[high]
            if any(a > b for a, b in zip(lo, hi)):
                self.report(ob.name, f"variation {low}", f"is greater than {high}")
        return out

    def animated_span(self, ob, frame_start, frame_end, fps):
        """(animated at the first frame, seconds until "Animated" is keyed off or None) of one object.
        Reports the keyings the engine does not follow: switched on after the first frame, or a
        passive body let go."""
        if _prebake_matrix(ob) is not None:
            return False, None  # a baked body: simulated, as it was before the bake
        source = compat.other_animation_of(ob, "rigid_body.kinematic")
        if source is not None:
            self.report(ob.name, "kinematic", f"\"Animated\" set by {source} is not read; only the keys of the "
                                              "object's own action are")
        flags = _keyed_animated(ob, frame_start, frame_end)
        if flags is None:
            return bool(ob.rigid_body.kinematic), None
        if not flags[0]:
            if any(flags):
                self.report(ob.name, "kinematic", "\"Animated\" keyed on after the first frame is not supported; "
                                                  "the object is simulated throughout")
            return False, None
        if all(flags):
            return True, None
        off = flags.index(False)
        if any(flags[off:]):
            self.report(ob.name, "kinematic", "\"Animated\" keyed on again after it was off is not supported; "
                                              "the object is simulated from the first time it goes off")
        if ob.rigid_body.type != "ACTIVE":
            self.report(ob.name, "kinematic", "\"Animated\" keyed off on a PASSIVE object is not supported; "
                                              "it follows its animation throughout")
            return True, None
        if off == 1:
            return False, None  # let go before any animated step: simulated from rest, as in Blender
        # Blender evaluates the flag before stepping into a frame: the body is free from the frame
        # before the first one keyed off, with the velocity of its last keyed step.
        return True, (off - 1) / fps

    def body(self, ob, animation, kinematic, animated_until_s=None):
        rbo = ob.rigid_body
        prebake = _prebake_matrix(ob)
        initial, scale = _transform(prebake if prebake is not None else ob.matrix_world)
        animated_throughout = kinematic and animated_until_s is None
        simulated = _native.body_role(rbo.type == "PASSIVE", bool(rbo.enabled),
                                      animated_throughout) == _native.BodyRole.SIMULATED
        shape = self.shape(ob, rbo, scale, simulated)
        if shape is None:
            return None
        body = {"name": ob.name, "type": rbo.type, "kinematic": animated_throughout,
                "enabled": bool(rbo.enabled),
                "shape": shape, "mass_kg": float(rbo.mass), "friction": float(rbo.friction),
                "restitution": float(rbo.restitution), "use_margin": bool(rbo.use_margin),
                "collision_margin_m": float(rbo.collision_margin),
                "linear_damping": float(rbo.linear_damping), "angular_damping": float(rbo.angular_damping),
                "collision_collections": sum(1 << i for i, on in enumerate(rbo.collision_collections) if on),
                "initial": initial}
        if rbo.use_deactivation:
            # Bullet's sleeping, as Blender sets it up: Start Deactivated only counts with Deactivation on.
            body["deactivation"] = {"enabled": True, "start_deactivated": bool(rbo.use_start_deactivated),
                                    "linear_speed": float(rbo.deactivate_linear_velocity),
                                    "angular_speed": float(rbo.deactivate_angular_velocity)}
        if kinematic and animation:
            body["animation"] = animation
        if animated_until_s is not None:
            # Blender lets the body go with the velocity of its last animated frame; so does the engine.
            body["animated_until_s"] = animated_until_s
        variation = self.variation(ob)
        if variation:
            body["variation"] = variation
        return body

    def warn_round_bodies_on_meshes(self, scene):
        """A cylinder or a many-sided hull against a MESH shape (thickened by its margin) may tilt
        or roll in the engine where Blender's rests (ODE's contacts of round shapes): name each such
        body that can meet a MESH."""
        bodies = scene["bodies"]
        meshes = [b for b in bodies if b["shape"]["type"] == "MESH"]
        for body in bodies:
            shape = body["shape"]
            round_shape = shape["type"] == "CYLINDER" or (shape["type"] == "CONVEX_HULL" and
                                                          len(shape["vertices_m"]) > 3 * 8)
            role = _native.body_role(body["type"] == "PASSIVE", body["enabled"], body["kinematic"])
            if role != _native.BodyRole.SIMULATED or not round_shape:
                continue
            touching = [m["name"] for m in meshes if m["collision_collections"] & body["collision_collections"]]
            if touching:
                self.report(body["name"], "collision_shape",
                            f"a {shape['type']} against the MESH shape of {touching[0]!r} may tilt or roll where "
                            "Blender's rests")

    # --- constraints ------------------------------------------------------------------------

    @staticmethod
    def _axes(rbc, kind, axes):
        enabled = [bool(getattr(rbc, f"use_limit_{kind}_{a}")) if a in axes else False for a in "xyz"]
        lo = [float(getattr(rbc, f"limit_{kind}_{a}_lower")) if a in axes else 0.0 for a in "xyz"]
        hi = [float(getattr(rbc, f"limit_{kind}_{a}_upper")) if a in axes else 0.0 for a in "xyz"]
        return {"enabled": enabled, "lower": lo, "upper": hi}

    @staticmethod
    def _springs(rbc, suffix):
        return {"enabled": [bool(getattr(rbc, f"use_spring_{suffix}{a}")) for a in "xyz"],
                "stiffness": [float(getattr(rbc, f"spring_stiffness_{suffix}{a}")) for a in "xyz"],
                "damping": [float(getattr(rbc, f"spring_damping_{suffix}{a}")) for a in "xyz"]}

    def constraint(self, ob, body_names):
        rbc = ob.rigid_body_constraint
        ends = []
        for slot, other in (("object1", rbc.object1), ("object2", rbc.object2)):
            if other is not None and other.name not in body_names:
                self.report(ob.name, slot, f"'{other.name}' is not an exported rigid body; constraint left out")
                return None
            ends.append(other.name if other is not None else "")
        if not any(ends):
            self.report(ob.name, "object1/object2", "no objects set; constraint left out")
            return None
        frame, _ = _transform(ob.matrix_world)
        c = {"name": ob.name, "type": rbc.type, "body_a": ends[0], "body_b": ends[1], "enabled": bool(rbc.enabled),
             "disable_collisions": bool(rbc.disable_collisions), "frame": frame,
             "breakable": bool(rbc.use_breaking), "breaking_threshold": float(rbc.breaking_threshold)}
        if rbc.use_breaking:
            self.report(ob.name, "breaking_threshold", "breaking is approximated: the engine compares the "
                                                       "joint's force per step along the constraint's axes with the "
                                                       "threshold, Bullet its solver impulses; near the threshold it "
                                                       "may break at another moment than in Blender")
        if rbc.use_override_solver_iterations:
            self.report(ob.name, "solver_iterations", "per-constraint solver iterations are not supported; "
                                                      "the world's iterations are used")
        # Only the settings Blender itself uses for the type (the others keep stale values).
        kind = rbc.type
        if kind == "HINGE":
            c["angular_limits"] = self._axes(rbc, "ang", "z")
        elif kind == "SLIDER":
            c["linear_limits"] = self._axes(rbc, "lin", "x")
        elif kind == "PISTON":
            c["linear_limits"] = self._axes(rbc, "lin", "x")
            c["angular_limits"] = self._axes(rbc, "ang", "x")
        elif kind in {"GENERIC", "GENERIC_SPRING"}:
            c["linear_limits"] = self._axes(rbc, "lin", "xyz")
            c["angular_limits"] = self._axes(rbc, "ang", "xyz")
            if kind == "GENERIC_SPRING":
                c["linear_springs"] = self._springs(rbc, "")
                c["angular_springs"] = self._springs(rbc, "ang_")
                springs = c["angular_springs"]
                if rbc.spring_type == "SPRING1" and any(springs["enabled"]):
                    self.report(ob.name, "spring_type", "SPRING1 (Blender's old spring) is simulated as a "
                                                        "damped spring like SPRING2")
                if any(on and d > 0 for on, d in zip(springs["enabled"], springs["damping"])):
                    # Bullet applies a spring explicitly each step; ODE's implicit spring loses a
                    # little more energy, so small swings die out sooner (fidelity corpus).
                    self.report(ob.name, "spring_damping_ang", "angular spring damping is approximated: small "
                                                               "swings settle sooner than in Blender")
            lin = c["linear_limits"]
            if not all(lin["enabled"]) or any(lin["lower"]) or any(lin["upper"]):
                self.report(ob.name, "linear limits", f"{kind} with free or limited linear axes is not supported "
                                                      "by the engine (lock all three at 0, or use SLIDER/PISTON); "
                                                      "constraint left out")
                return None
            if kind == "GENERIC_SPRING" and any(c["linear_springs"]["enabled"]):
                self.report(ob.name, "linear springs", "linear springs need free linear axes, which the engine "
                                                       "does not support; ignored")
        elif kind == "MOTOR":
            c.update({"motor_linear_enabled": bool(rbc.use_motor_lin),
                      "motor_angular_enabled": bool(rbc.use_motor_ang),
                      "motor_linear_target_velocity": float(rbc.motor_lin_target_velocity),
                      "motor_linear_max_impulse": float(rbc.motor_lin_max_impulse),
                      "motor_angular_target_velocity": float(rbc.motor_ang_target_velocity),
                      "motor_angular_max_impulse": float(rbc.motor_ang_max_impulse)})
        return c

    # --- world --------------------------------------------------------------------------------

    def world(self):
        scene, rbw = self.scene, self.rbw
        cache = rbw.point_cache
        if rbw.use_split_impulse:
            self.report("Rigid Body World", "use_split_impulse", "not supported; ignored")
        gravity = _vec(scene.gravity) if scene.use_gravity else [0.0, 0.0, 0.0]
        return {"gravity": gravity, "time_scale": float(rbw.time_scale),
                "substeps_per_frame": int(rbw.substeps_per_frame), "solver_iterations": int(rbw.solver_iterations),
                "frame_start": int(cache.frame_start), "frame_end": int(cache.frame_end),
                "fps": scene.render.fps / scene.render.fps_base}

    def sample_animation(self, objects, frame_start, frame_end, fps):
        """Animated ('kinematic') objects' world transforms at every frame of the range."""
        tracks = {ob.name: {"times_s": [], "transforms": []} for ob in objects}
        for frame in range(frame_start, frame_end + 1):
            self.scene.frame_set(frame)
            for ob in objects:
                transform, _ = _transform(ob.matrix_world)
                tracks[ob.name]["times_s"].append((frame - frame_start) / fps)
                tracks[ob.name]["transforms"].append(transform)
        return tracks

    def body_objects(self):
        """The objects that become bodies, by name: every rigid body of the world's collection but
        the children of a compound (part of its shape)."""
        members = set(self.rbw.collection.objects)
        objects = [ob for ob in members if ob.rigid_body is not None and not (
            ob.parent is not None and ob.parent.rigid_body is not None
            and ob.parent.rigid_body.collision_shape == "COMPOUND" and ob.parent in members)]
        return sorted(objects, key=lambda ob: ob.name)

    def simulated_names(self):
        """Names of the bodies the engine will move, by its own rule (BodyRole), read from the
        settings without exporting any shape."""
        if self.rbw is None or self.rbw.collection is None:
            return []
        world = self.world()
        names = []
        for ob in self.body_objects():
            animated, until = self.animated_span(ob, world["frame_start"], world["frame_end"], world["fps"])
            role = _native.body_role(ob.rigid_body.type == "PASSIVE", bool(ob.rigid_body.enabled),
                                     animated and until is None)
            if role == _native.BodyRole.SIMULATED:
                names.append(ob.name)
        return names

    def export(self):
        if self.rbw is None or self.rbw.collection is None:
            self.report(self.scene.name, "rigid body world", "the scene has no rigid body world or its collection "
                                                              "is empty (Scene Properties > Rigid Body World)")
            return ExportResult(None, self.problems)
        world = self.world()
        frame_start, frame_end, fps = world["frame_start"], world["frame_end"], world["fps"]
        objects = self.body_objects()
        frame_was, subframe_was = self.scene.frame_current, self.scene.frame_subframe
        try:
            spans = {ob.name: self.animated_span(ob, frame_start, frame_end, fps) for ob in objects}
            animated = [ob for ob in objects if spans[ob.name][0]]
            animations = self.sample_animation(animated, frame_start, frame_end, fps) if animated else {}
            # Initial transforms are those at the rigid body world's first frame.
            self.scene.frame_set(frame_start)
            bodies = [b for b in (self.body(ob, animations.get(ob.name), *spans[ob.name]) for ob in objects)
                      if b is not None]
            names = {b["name"] for b in bodies}
            constraint_objects = []
            if self.rbw.constraints is not None:
                constraint_objects = sorted((ob for ob in self.rbw.constraints.objects
                                             if ob.rigid_body_constraint is not None), key=lambda ob: ob.name)
            constraints = [c for c in (self.constraint(ob, names) for ob in constraint_objects) if c is not None]
        finally:
            self.scene.frame_set(frame_was, subframe=subframe_was)
        scene = {"format": SCENE_FORMAT, "version": SCENE_VERSION, "name": self.scene.name, "world": world,
                 "bodies": bodies, "constraints": constraints}
        self.warn_round_bodies_on_meshes(scene)
        return ExportResult(scene, self.problems)


def export_scene(scene, depsgraph=None):
    """Export a Blender scene; returns ExportResult(scene dict or None, problems)."""
    return SceneExporter(scene, depsgraph).export()


def simulated_object_names(scene):
    """The rigid bodies of `scene` the engine would move, before any library exists."""
    return SceneExporter(scene).simulated_names()


def export_and_validate(context):
    """Export the context scene and check it with the engine's own validator.

    Returns (ExportResult, validation problems). The scene is usable when it is not None and the
    validation list is empty; export problems are warnings about what was approximated or left out.
    """
    from . import _native
    result = export_scene(context.scene, context.evaluated_depsgraph_get())
    if result.scene is None:
        return result, []
    return result, list(_native.validate_scene_json(result.to_json()))


classes = ()
