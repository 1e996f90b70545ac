"""Benchmark: a script plays the user. Goal boxes are queries; the best world by "constraints
satisfied" (ties: the missing bodies end nearest their goals) is refined on a body that misses its
box, from one of that body's collisions, and a refined world replaces it when it does better;
repeat until the goal holds or the budget is spent. Reports refinement steps and worlds simulated (the paper's users needed 18 refinements
for the staircase and about an hour for the letters).

blender -b blend_examples/NAME/NAME.blend --python tests/bench/bench_scripted_goal.py [-- MAX_ATTEMPTS]
Prints a table and `BENCH scripted_goal_NAME_refinements`, `..._worlds` and `..._reached` (1/0).
"""
import os
import subprocess
import sys
import tempfile
import time

import bpy
import numpy as np
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import many_worlds  # noqa: E402
from many_worlds import _native, cli  # noqa: E402
from many_worlds.core import paths  # noqa: E402
from many_worlds.export import export_and_validate  # noqa: E402

# Per example: the goal as (tracked body, goal object, time window in s, height above the goal
# object in m where the body's centre may be) boxes, all to hold.
GOALS = {
    "marble_run": [("Marble", "GoalBasket", (7.0, 8.0), 0.3)],
    "pachinko_letters": [(f"Letter{i}_{c}", f"Slot{i}_{c}", (5.0, 6.0), 0.5) for i, c in enumerate("WORLDS", 1)],
    "spiral_staircase": [("Pelvis", "Step48", (8.0, 10.0), 1.0)],   # the lowest step, at the end
}
# Where leaving a region means the attempt has failed from then on (the staircase has no railing):
# (centre x, y, radius in m). Progress is then measured where the body left it, and refinements
# branch before that.
FOOTPRINTS = {"spiral_staircase": (0.0, 0.0, 1.6)}
INITIAL_WORLDS = 24
CHILDREN_PER_REFINEMENT = 16
MAX_REFINEMENT_ATTEMPTS = int(sys.argv[sys.argv.index("--") + 1]) if "--" in sys.argv else 60


def engine(*args):
    result = subprocess.run([paths.engine_path(), *args], capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(result.stderr.strip())


def goal_objects(target):
    """The goal's objects: every object whose name starts with `target`."""
    return [ob for ob in bpy.data.objects if ob.name.startswith(target)]


def goal_points(goals):
    """Per goal, the world point a body resting at the goal would have (the goal's top centre)."""
    points = []
    for _, target, _, lift in goals:
        corners = [ob.matrix_world @ Vector(c) for ob in goal_objects(target) for c in ob.bound_box]
        centre = sum(corners, Vector()) / len(corners)
        points.append((centre.x, centre.y, max(c.z for c in corners) + lift / 2))
    return points


def goal_boxes(goals, body_names):
    """One positive QueryBox per goal, around the goal object as the scene camera sees it."""
    scene = bpy.context.scene
    view, projection, (width, height) = cli.camera_view(scene.camera.name)
    boxes = []
    for body, target, window, lift in goals:
        # The goal object and the space above it where the tracked body's centre rests.
        world = [ob.matrix_world @ Vector(c) for ob in goal_objects(target) for c in ob.bound_box]
        corners = [world_to_camera_view(scene, scene.camera, p + Vector((0, 0, dz))) for p in world for dz in (0, lift)]
        x0, x1 = min(p.x for p in corners), max(p.x for p in corners)
        y0, y1 = min(p.y for p in corners), max(p.y for p in corners)
        boxes.append(_native.QueryBox(view, projection, (width, height),
                                      (x0 * width, y0 * height, x1 * width, y1 * height),
                                      bodies=[body_names.index(body)], time_window=window))
    return boxes


def satisfied_boxes(index, boxes, world):
    """Which boxes world satisfies (one query per box keeps the per-box answer)."""
    return [world in set(int(w) for w in index.query([box])["matching"]) for box in boxes]


def left_footprint_frame(path, footprint):
    """First frame where the path is outside the footprint, or None."""
    if footprint is None:
        return None
    cx, cy, radius = footprint
    outside = np.hypot(path[:, 0] - cx, path[:, 1] - cy) > radius
    return int(np.argmax(outside)) if outside.any() else None


def score(library, index, boxes, goals, points, body_names, world, satisfied, footprint):
    """(boxes satisfied, minus the summed distance to their goals of where the missing bodies ended,
    or left the footprint)."""
    met = satisfied_boxes(index, boxes, world)
    positions = library.positions(world)
    distance = 0.0
    for (body, _, _, _), point, ok in zip(goals, points, met):
        if not ok:
            path = positions[body_names.index(body)]
            left = left_footprint_frame(path, footprint)
            end = path[-1] if left is None else path[left]
            distance += float(np.linalg.norm(end - np.asarray(point)))
    return (satisfied, -distance)


def best_world(library, index, boxes, goals, points, body_names, footprint):
    result = index.query(boxes)
    candidates = [(int(w), int(n)) for w, n in zip(result["world_indices"], result["boxes_satisfied"])]
    top = max(n for _, n in candidates)
    scored = [(score(library, index, boxes, goals, points, body_names, w, n, footprint), -w, w)
              for w, n in candidates if n == top]
    best = max(scored)
    return best[2], best[0]


def branch_candidates(library, world, body, body_name, window_start, footprint):
    """Times to branch from, latest first: the body's collisions before its goal window, or before
    it left the footprint (where its path can change), and should those run out, every quarter second."""
    left = left_footprint_frame(library.positions(world)[body], footprint)
    if left is not None:
        window_start = min(window_start, left / library.world_info(world).record_hz)
    collisions = {round(t, 4) for t, b, _, _ in library.contacts(world) if b == body and 0 < t < window_start}
    grid = {round(k * 0.25, 4) for k in range(int(window_start / 0.25))}
    return sorted(collisions | grid, reverse=True)


def play(name, goals, folder):
    footprint = FOOTPRINTS.get(name)
    result, problems = export_and_validate(bpy.context)
    if result.scene is None or problems:
        raise SystemExit(f"{name}: cannot export: {problems}")
    scene_json = os.path.join(folder, "scene.json")
    with open(scene_json, "w") as f:
        f.write(result.to_json())
    library_path = os.path.join(folder, "goal.mwb")
    engine("sample", "--scene", scene_json, "--out", library_path, "--worlds", f"0:{INITIAL_WORLDS}")
    worlds_simulated = INITIAL_WORLDS
    library = _native.Library(library_path)
    scene = _native.Scene.from_json(library.header["scene_json"])
    index = _native.PathIndex(_native.body_bounding_radii(scene))
    index.add_library(library)
    boxes = goal_boxes(goals, scene.body_names)
    points = goal_points(goals)
    best, best_score = best_world(library, index, boxes, goals, points, scene.body_names, footprint)
    refinements = attempts = 0
    tried = set()
    while best_score[0] < len(boxes) and attempts < MAX_REFINEMENT_ATTEMPTS:
        met = satisfied_boxes(index, boxes, best)
        goal = met.index(False)
        body = scene.body_names.index(goals[goal][0])
        candidates = [t for t in branch_candidates(library, best, body, goals[goal][0], goals[goal][2][0], footprint)
                      if (best, body, t) not in tried]
        if not candidates:
            break
        # The middle one first: late enough to keep what works, early enough to matter.
        t_branch = candidates[len(candidates) // 2]
        tried.add((best, body, t_branch))
        engine("refine", "--library", library_path, "--world", str(best), "--bodies", str(body),
               "--time", repr(t_branch), "--count", str(CHILDREN_PER_REFINEMENT))
        attempts += 1
        worlds_simulated += CHILDREN_PER_REFINEMENT
        library.poll()
        index.add_library(library)
        candidate, candidate_score = best_world(library, index, boxes, goals, points, scene.body_names, footprint)
        if candidate_score > best_score:
            best, best_score = candidate, candidate_score
            refinements += 1
    count = best_score[0]
    return {"refinements": refinements, "attempts": attempts, "worlds": worlds_simulated, "reached": count == len(boxes),
            "boxes": f"{count}/{len(boxes)}", "best": best}


def main():
    name = os.path.splitext(os.path.basename(bpy.data.filepath))[0]
    if name not in GOALS:
        raise SystemExit(f"no scripted goal for {name} (have: {', '.join(GOALS)})")
    many_worlds.register()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        outcome = play(name, GOALS[name], folder)
    elapsed = time.perf_counter() - start
    print(f"{name}: goal {'reached' if outcome['reached'] else 'not reached'} ({outcome['boxes']} boxes, world "
          f"{outcome['best']}) after {outcome['refinements']} refinements ({outcome['attempts']} tried), "
          f"{outcome['worlds']} worlds simulated, {elapsed:.1f} s")
    print(f"BENCH scripted_goal_{name}_refinements {outcome['refinements']}")
    print(f"BENCH scripted_goal_{name}_worlds {outcome['worlds']}")
    print(f"BENCH scripted_goal_{name}_reached {int(outcome['reached'])}")


main()
