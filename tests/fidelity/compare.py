"""Runs a fidelity scene both ways, Blender's own simulation (Bullet) and the engine with
perturbation off, and compares the kind of outcome (SPEC §12): which bodies fall and come to
rest, where they rest, how fast anything goes, which breakable constraints end broken.

Inside Blender:
    blender -b --factory-startup --python-exit-code 1 --python tests/fidelity/compare.py -- \
        [SCENE ...] [--out DIR]
prints each scene's JSON report and a one-line verdict, writes DIR/<scene>.json when --out is
given, and exits 1 if a scene fails.

Both sides are compared at Blender's frames: Blender frame f is engine time (f - frame_start) / fps.
A scene passes when every criterion holds, or when every body or constraint on which a criterion
fails is named by an export warning ("object: setting: reason"); a warning on a constraint covers
the two bodies it joins and one on a body covers its constraints.

The engine's world is simulated in a forked copy of Blender, so that a world which aborts inside
ODE fails its scene ("crashed") instead of ending Blender and the rest of the suite.
"""
import json
import os
import pickle
import select
import signal
import sys
import time
import traceback

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
for path in (os.path.join(ROOT, "addon"), HERE):
    if path not in sys.path:
        sys.path.insert(0, path)

import scenes  # noqa: E402

# Where an older Blender saved the corpus's scenes (save_scenes.py): a Blender without the tools
# some scenes are built with (Cell Fracture is not bundled from 4.2 on) opens them from there, as
# an animator opens an older file.
SCENES_DIR = os.environ.get("MWB_FIDELITY_SCENES")

REST_SPEED_MPS = 0.05       # at rest: slower than this ...
REST_WINDOW_S = 0.5         # ... over the last half second
HEIGHT_TOLERANCE_M = 0.01   # resting heights within a centimetre
SPEED_RATIO = 1.5           # nothing faster than 1.5x Bullet's fastest body
FALL_M = 0.05               # a body fell if it ends this much lower than it started
BROKEN_DISTANCE_M = 0.05    # a constraint broke if its bodies' distance changed by more
ENGINE_TIMEOUT_S = 120      # a world that takes longer has hung

PASS, COVERED, FAIL = "PASS", "PASS (divergence covered by export warnings)", "FAIL"


# --- running a scene ------------------------------------------------------------------------

def ensure_registered():
    """Register the add-on once (its per-object properties are needed by the export)."""
    import many_worlds
    if not hasattr(bpy.types.Object, "mwb_variation"):
        many_worlds.register()


def rigid_body_objects(scene):
    """The objects of the Rigid Body World's collection that have a rigid body, by name."""
    rbw = scene.rigidbody_world
    return sorted((ob for ob in rbw.collection.objects if ob.rigid_body is not None), key=lambda ob: ob.name)


def breakable_constraints(scene):
    """{constraint name: (object1 name, object2 name)} of the enabled breakable constraints."""
    rbw = scene.rigidbody_world
    if rbw.constraints is None:
        return {}
    out = {}
    for ob in rbw.constraints.objects:
        rbc = ob.rigid_body_constraint
        if rbc is not None and rbc.enabled and rbc.use_breaking and rbc.object1 and rbc.object2:
            out[ob.name] = (rbc.object1.name, rbc.object2.name)
    return dict(sorted(out.items()))


def simulate_in_blender(scene):
    """Step Blender's simulation through every frame of the range; returns
    ({name: float64 (frames, 3) object origins}, {name: final unit quaternion (w, x, y, z)}, seconds)."""
    objects = rigid_body_objects(scene)
    start = time.perf_counter()
    scene.frame_set(scene.frame_start)
    tracks = {ob.name: [] for ob in objects}
    for frame in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(frame)
        for ob in objects:
            tracks[ob.name].append(tuple(ob.matrix_world.translation))
    final = {ob.name: np.array(ob.matrix_world.to_quaternion()) for ob in objects}
    elapsed = time.perf_counter() - start
    scene.frame_set(scene.frame_start)
    return {name: np.array(rows) for name, rows in tracks.items()}, final, elapsed


def simulate_in_engine(scene):
    """Export the scene with the add-on and simulate one unperturbed world in-process.
    Returns a dict: tracks ({name: (frames, 3)} at Blender's frames, or None if the scene could not
    be simulated), final orientations ({name: (w, x, y, z)}), warnings, validation errors, status,
    joints broken at the last checkpoint, and seconds spent exporting and simulating."""
    from many_worlds.export import export_and_validate
    out = {"tracks": None, "final_orientations": {}, "warnings": [], "validation_errors": [],
           "status": "not run", "reject_reason": "", "engine_joint_broken": {}, "export_s": 0.0, "engine_s": 0.0}
    start = time.perf_counter()
    result, invalid = export_and_validate(bpy.context)
    out["export_s"] = time.perf_counter() - start
    out["warnings"] = list(result.problems)
    out["validation_errors"] = list(invalid)
    if result.scene is None or invalid:
        return out
    start = time.perf_counter()
    world = run_isolated(simulate_world, result.to_json())
    out["engine_s"] = time.perf_counter() - start
    out["status"], out["reject_reason"] = world["status"], world["reject_reason"]
    if world["status"] != "ok":
        return out
    fps = scene.render.fps / scene.render.fps_base
    frame_start = result.scene["world"]["frame_start"]
    frames = range(scene.frame_start, scene.frame_end + 1)
    index = [round((f - frame_start) * world["record_hz"] / fps) for f in frames]
    positions = world["positions"]
    if index[-1] >= positions.shape[1]:
        raise RuntimeError(f"the engine recorded {positions.shape[1]} frames, Blender's range needs {index[-1] + 1}")
    names = world["body_names"]
    out["tracks"] = {name: positions[k, index] for k, name in enumerate(names)}
    out["final_orientations"] = {name: world["orientations"][k, index[-1]] for k, name in enumerate(names)}
    out["engine_joint_broken"] = world["joint_broken"]
    return out


def simulate_world(scene_json):
    """One world of the scene with perturbation off, simulated to the end of the frame range."""
    from many_worlds import _native
    native_scene = _native.Scene.from_json(scene_json)
    params = _native.SimulationParameters()
    params.perturb = False
    params.stop_at_rest = False
    world = _native.sample(native_scene, params, 0, 0, 1, threads=1)[0]
    checkpoints = world.checkpoints
    broken = checkpoints[-1]["joint_broken"] if checkpoints else []
    return {"status": world.status, "reject_reason": world.reject_reason, "record_hz": world.record_hz,
            "positions": world.positions, "orientations": world.orientations,
            "body_names": list(native_scene.body_names),
            "joint_broken": {name: bool(b) for name, b in zip(native_scene.constraint_names, broken)}}


def run_isolated(function, *args, timeout_s=ENGINE_TIMEOUT_S):
    """function(*args) in a forked copy of this process, so that an abort inside ODE fails the
    scene (status "crashed") instead of ending Blender and the whole suite."""
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        code = 0
        try:
            os.close(read_end)
            with os.fdopen(write_end, "wb") as pipe:
                pickle.dump(function(*args), pipe)
        except BaseException:
            traceback.print_exc()
            code = 1
        finally:
            os._exit(code)
    os.close(write_end)
    chunks, deadline = [], time.monotonic() + timeout_s
    with os.fdopen(read_end, "rb") as pipe:
        while True:
            ready, _, _ = select.select([pipe], [], [], max(0.0, deadline - time.monotonic()))
            if not ready:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                return {"status": "hung", "reject_reason": f"no result after {timeout_s} s"}
            chunk = os.read(pipe.fileno(), 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
    _, status = os.waitpid(pid, 0)
    if os.WIFSIGNALED(status):
        return {"status": "crashed", "reject_reason": f"the process died of signal {os.WTERMSIG(status)} "
                                                      f"({signal.Signals(os.WTERMSIG(status)).name})"}
    if os.WEXITSTATUS(status) != 0 or not chunks:
        return {"status": "failed",
                "reject_reason": f"the simulation raised an exception (exit {os.WEXITSTATUS(status)})"}
    return pickle.loads(b"".join(chunks))


# --- outcomes -------------------------------------------------------------------------------

def body_outcome(track, fps):
    """What one body did, from its origin at every frame: fell, at rest, final height, top speed."""
    speeds = np.linalg.norm(np.diff(track, axis=0), axis=1) * fps
    window = max(1, round(REST_WINDOW_S * fps))
    return {"fell": bool(track[0, 2] - track[-1, 2] > FALL_M),
            "at_rest": bool(np.all(speeds[-window:] < REST_SPEED_MPS)),
            "final_z_m": float(track[-1, 2]),
            "final_speed_mps": float(np.max(speeds[-window:])),
            "max_speed_mps": float(np.max(speeds)) if len(speeds) else 0.0,
            "final_position_m": [round(float(c), 4) for c in track[-1]]}


def tilt_deg(q):
    """Angle between the body's local Z axis and world Z, degrees (0: as upright as it started
    for bodies modelled upright)."""
    w, x, y, z = q
    return float(np.degrees(np.arccos(np.clip(1 - 2 * (x * x + y * y), -1, 1))))


def rotation_apart_deg(q1, q2):
    """The angle between two unit quaternions' rotations, degrees."""
    return float(np.degrees(2 * np.arccos(np.clip(abs(np.dot(q1, q2)), -1, 1))))


def constraint_broken(tracks, pair):
    """(broken, change of the distance between the two bodies' origins in metres)."""
    a, b = (tracks.get(name) for name in pair)
    if a is None or b is None:
        return None, None
    change = float(np.linalg.norm(a[-1] - b[-1]) - np.linalg.norm(a[0] - b[0]))
    return abs(change) > BROKEN_DISTANCE_M, change


def criterion(name, divergent, numbers, rule):
    """One criterion's result: it holds when no body or constraint diverges."""
    return {"criterion": name, "rule": rule, "ok": not divergent, "divergent": sorted(divergent), "numbers": numbers}


def compare_outcomes(active, bullet, ours, constraints, fps):
    """The criteria of SPEC §12 for the ACTIVE bodies `active` and the breakable `constraints`.
    Returns (criteria, Bullet's body outcomes, ours)."""
    b = {name: body_outcome(bullet[name], fps) for name in active}
    o = {name: body_outcome(ours[name], fps) for name in active if name in ours}
    missing = sorted(set(active) - set(o))
    present = [name for name in active if name in o]

    def names(outcomes, key):
        return {n for n in present if outcomes[n][key]}

    results = []
    fell_b, fell_o = names(b, "fell"), names(o, "fell")
    results.append(criterion("same_bodies_fall", (fell_b ^ fell_o) | set(missing),
                             {"bullet": sorted(fell_b), "ours": sorted(fell_o), "not_exported": missing},
                             f"the same bodies end more than {FALL_M} m below their start"))
    rest_b, rest_o = names(b, "at_rest"), names(o, "at_rest")
    results.append(criterion("same_bodies_rest", rest_b ^ rest_o,
                             {"bullet": sorted(rest_b), "ours": sorted(rest_o)},
                             f"the same bodies end at rest (< {REST_SPEED_MPS} m/s over the last {REST_WINDOW_S} s)"))
    results.append(criterion("at_rest_where_bullet_rests", rest_b - rest_o,
                             {"bullet_only": sorted(rest_b - rest_o)},
                             "every body at rest in Bullet is at rest in ours"))
    heights = {n: {"bullet_z_m": round(b[n]["final_z_m"], 4), "ours_z_m": round(o[n]["final_z_m"], 4),
                   "dz_m": round(o[n]["final_z_m"] - b[n]["final_z_m"], 4)} for n in sorted(rest_b & rest_o)}
    off = {n for n, h in heights.items() if abs(h["dz_m"]) > HEIGHT_TOLERANCE_M}
    results.append(criterion("resting_heights", off, heights,
                             f"resting heights within {HEIGHT_TOLERANCE_M} m of Bullet's"))
    fastest_b = max(present, key=lambda n: b[n]["max_speed_mps"], default=None)
    top_b = b[fastest_b]["max_speed_mps"] if fastest_b else 0.0
    # A body slower than the rest speed is at rest in both simulations, however still Bullet's is.
    limit = max(SPEED_RATIO * top_b, REST_SPEED_MPS)
    too_fast = {n for n in present if o[n]["max_speed_mps"] > limit}
    fastest_o = max(present, key=lambda n: o[n]["max_speed_mps"], default=None)
    results.append(criterion("max_speed", too_fast,
                             {"bullet_fastest": fastest_b, "bullet_max_mps": round(top_b, 3),
                              "ours_fastest": fastest_o,
                              "ours_max_mps": round(o[fastest_o]["max_speed_mps"], 3) if fastest_o else 0.0},
                             f"no body faster than {SPEED_RATIO}x Bullet's fastest body (or the rest speed)"))
    if constraints:
        breaks = {}
        for cname, pair in constraints.items():
            broken_b, change_b = constraint_broken(bullet, pair)
            broken_o, change_o = constraint_broken(ours, pair)
            breaks[cname] = {"bodies": list(pair), "bullet_broken": broken_b, "ours_broken": broken_o,
                             "bullet_distance_change_m": None if change_b is None else round(change_b, 4),
                             "ours_distance_change_m": None if change_o is None else round(change_o, 4)}
        results.append(criterion("same_constraints_break",
                                 {c for c, v in breaks.items() if v["bullet_broken"] != v["ours_broken"]}, breaks,
                                 f"the same breakable constraints end broken (bodies' distance changed > "
                                 f"{BROKEN_DISTANCE_M} m)"))
    return results, b, o


def covering_warnings(item, warnings, links):
    """The export warnings that name `item` (a body or constraint) or a constraint/body linked to it."""
    linked = {item} | set(links.get(item, ()))
    return [w for w in warnings if w.split(":", 1)[0] in linked]


def linked_objects(scene):
    """{object name: names linked to it}: a constraint's two bodies, and a body's constraints."""
    links = {}
    rbw = scene.rigidbody_world
    for ob in (rbw.constraints.objects if rbw.constraints else ()):
        rbc = ob.rigid_body_constraint
        ends = [o.name for o in (rbc.object1, rbc.object2) if o is not None] if rbc else []
        links.setdefault(ob.name, set()).update(ends)
        for end in ends:
            links.setdefault(end, set()).add(ob.name)
    return links


def body_details(active, bullet, bullet_final, engine, b, o):
    """Per body: Bullet's outcome and ours, final tilts, and how far apart the two end."""
    bodies = {}
    for n in active:
        bodies[n] = {"bullet": dict(b[n], final_tilt_deg=round(tilt_deg(bullet_final[n]), 1)), "ours": None}
        if n in o:
            q = engine["final_orientations"][n]
            bodies[n]["ours"] = dict(o[n], final_tilt_deg=round(tilt_deg(q), 1))
            bodies[n]["final_apart_m"] = round(float(np.linalg.norm(bullet[n][-1] - engine["tracks"][n][-1])), 4)
            bodies[n]["final_rotation_apart_deg"] = round(rotation_apart_deg(bullet_final[n], q), 1)
    return bodies


def run_scene(name):
    """Build scene `name` in the current (fresh) file (or open it from SCENES_DIR), run both
    simulations and compare.
    Returns the report dict; report["verdict"] is PASS, COVERED or FAIL."""
    ensure_registered()
    build, what = scenes.SCENES[name]
    start = time.perf_counter()
    if SCENES_DIR:
        bpy.ops.wm.open_mainfile(filepath=os.path.join(SCENES_DIR, f"{name}.blend"), load_ui=False)
    else:
        build()
    build_s = time.perf_counter() - start
    scene = bpy.context.scene
    fps = scene.render.fps / scene.render.fps_base
    active = [ob.name for ob in rigid_body_objects(scene) if ob.rigid_body.type == "ACTIVE"]
    constraints = breakable_constraints(scene)
    links = linked_objects(scene)
    bullet, bullet_final, blender_s = simulate_in_blender(scene)
    engine = simulate_in_engine(scene)
    report = {"scene": name, "what": what, "bodies_simulated": len(active),
              "frames": scene.frame_end - scene.frame_start + 1, "fps": fps,
              "warnings": engine["warnings"], "validation_errors": engine["validation_errors"],
              "engine_status": engine["status"], "reject_reason": engine["reject_reason"],
              "timing_s": {"build": round(build_s, 3), "blender": round(blender_s, 3),
                           "export": round(engine["export_s"], 3), "engine": round(engine["engine_s"], 3)}}
    b = {n: body_outcome(bullet[n], fps) for n in active}
    if engine["tracks"] is None:
        reason = "; ".join(engine["validation_errors"]) or f"world {engine['status']}: {engine['reject_reason']}"
        report.update(criteria=[], bodies=body_details(active, bullet, bullet_final, engine, b, {}), verdict=FAIL,
                      failed=[f"not simulated: {reason}"], covered=[])
        return report
    criteria, b, o = compare_outcomes(active, bullet, engine["tracks"], constraints, fps)
    for c in criteria:
        c["covered_by"] = {item: covering_warnings(item, engine["warnings"], links) for item in c["divergent"]}
        c["covered"] = not c["ok"] and all(c["covered_by"].values())
    if engine["engine_joint_broken"]:
        report["engine_joint_broken_last_checkpoint"] = {k: v for k, v in engine["engine_joint_broken"].items()
                                                         if k in constraints}
    report["criteria"] = criteria
    report["bodies"] = body_details(active, bullet, bullet_final, engine, b, o)
    failed = [c for c in criteria if not c["ok"]]
    report["failed"] = [c["criterion"] for c in failed if not c["covered"]]
    report["covered"] = [c["criterion"] for c in failed if c["covered"]]
    report["verdict"] = PASS if not failed else (COVERED if not report["failed"] else FAIL)
    return report


def verdict_line(report):
    """One line: scene, verdict, and the failed criteria with their divergent objects."""
    line = f"{report['scene']}: {report['verdict']}"
    parts = []
    for c in report.get("criteria", []):
        if not c["ok"]:
            mark = "covered" if c["covered"] else "FAILED"
            parts.append(f"{c['criterion']} {mark} on {', '.join(c['divergent'])}")
    if report["verdict"] == FAIL and not report.get("criteria"):
        parts = report["failed"]
    return line + (" -- " + "; ".join(parts) if parts else "")


def failure_message(report):
    """The failed criteria with their numbers, for an assertion message."""
    lines = [verdict_line(report)]
    for c in report.get("criteria", []):
        if not c["ok"] and not c["covered"]:
            lines.append(f"  {c['criterion']} ({c['rule']}): divergent {c['divergent']}; "
                         f"numbers {json.dumps(c['numbers'])}")
    if report["warnings"]:
        lines.append(f"  export warnings: {report['warnings']}")
    return "\n".join(lines)


def fresh_file():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ensure_registered()


def main(argv):
    out = None
    if "--out" in argv:
        k = argv.index("--out")
        out = argv[k + 1]
        argv = argv[:k] + argv[k + 2:]
    names = argv or list(scenes.SCENES)
    unknown = [n for n in names if n not in scenes.SCENES]
    if unknown:
        print(f"unknown scenes {unknown}; known: {list(scenes.SCENES)}")
        return 2
    failed = 0
    lines = []
    for name in names:
        fresh_file()
        report = run_scene(name)
        print(json.dumps(report, indent=1))
        lines.append(verdict_line(report))
        failed += report["verdict"] == FAIL
        if out:
            os.makedirs(out, exist_ok=True)
            with open(os.path.join(out, f"{name}.json"), "w") as f:
                json.dump(report, f, indent=1)
    print("\n".join(lines))
    return 1 if failed else 0


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    sys.exit(main(args))
