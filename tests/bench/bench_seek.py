"""Benchmark: goal search on an example, with the goal its README states in full, from several
first batches, so that one lucky (or unlucky) start does not decide the figure.

    blender -b blend_examples/NAME/NAME.blend --python tests/bench/bench_seek.py [-- BUDGET_WORLDS [BUDGET_S [GOAL]]]

GOAL names the goal (default: the example's own, NAME); an example may have more than one
(siggraph_letters.blend also has siggraph_upright).

Exports the scene; then for each of MWB_SEEK_BATCHES first batches (default 5: base seeds 0 to 4,
MWB_SEEK_FIRST_BATCH worlds each, default 32; MWB_SEEK_SEEDS=2,3 runs only those) samples the batch as a user would, counts the worlds
of it that already meet the goal, and runs `mwb-engine seek` with the goal's boxes (drawn in the
scene camera's view, or in a top view for footprints) and pose parts until one world meets them
all or the budget is spent. The world it reports is checked again with the browser's own query
(its boxes, and its pose parts where the module offers them). Prints a line per batch, then the
median and the worst, and
`BENCH seek_NAME_first_batch_met` (worlds of the first batches meeting the goal already, all
batches together: 0 when the example tests a search), `BENCH seek_NAME_reached` (batches that
reached it), `BENCH seek_NAME_worst_worlds`, `BENCH seek_NAME_worst_s`, and the medians
`BENCH seek_NAME_worlds` and `BENCH seek_NAME_s` (worlds simulated and wall time, the first batch
included), NAME being the goal's. `BENCH seek_NAME_children_losing_met_pct` and
`_children_gaining_pct`: of the worlds its refinements made, all batches together, the share that
lost a goal part their parent met and the share meeting more parts than their parent (the parts
the browser's query holds; not printed when it holds none).
"""
import contextlib
import json
import math
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

FIRST_BATCH = int(os.environ.get("MWB_SEEK_FIRST_BATCH", 32))
BATCHES = int(os.environ.get("MWB_SEEK_BATCHES", 5))
SEEDS = [int(s) for s in os.environ["MWB_SEEK_SEEDS"].split(",")] if os.environ.get("MWB_SEEK_SEEDS") else range(BATCHES)
ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
BUDGET_WORLDS = int(ARGS[0]) if ARGS else 20000
BUDGET_S = float(ARGS[1]) if len(ARGS) > 1 else 600.0
GOAL_NAME = ARGS[2] if len(ARGS) > 2 else None
TOP_VIEW_SIZE = 1000  # pixels of the orthographic views' square viewport


def corners(names, lift=0.0, pad=0.0):
    """World corners of the named objects' bounding boxes, raised by up to `lift` and grown by `pad`."""
    points = []
    for name in names:
        ob = bpy.data.objects[name]
        for c in ob.bound_box:
            p = ob.matrix_world @ Vector(c)
            for dz in (0.0, lift):
                for dx in (-pad, pad):
                    points.append(p + Vector((dx, 0, dz - pad)))
                    points.append(p + Vector((dx, 0, dz + pad)))
    return points


def camera_box(points, objects, *, negative=False, window=None, after=None, swept=False):
    """A goal box around world points as the scene camera sees them."""
    scene = bpy.context.scene
    view, projection, (width, height) = cli.camera_view(scene.camera.name)
    screen = [world_to_camera_view(scene, scene.camera, p) for p in points]
    rect = [min(p.x for p in screen) * width, min(p.y for p in screen) * height,
            max(p.x for p in screen) * width, max(p.y for p in screen) * height]
    return {"view": np.asarray(view).ravel().tolist(), "projection": np.asarray(projection).ravel().tolist(),
            "viewport": [width, height], "rect": rect, "objects": objects, "negative": negative,
            "time_window": window, "after": after, "swept": swept}


def ortho_box(right, up, x0, y0, x1, y1, objects, *, half_size=6.0, negative=False, window=None, after=None,
              swept=False):
    """A goal box seen through an orthographic view (a square of half_size metres) whose screen x
    and y run along the world directions `right` and `up`: it holds every point whose coordinates
    along them lie in [x0, x1] × [y0, y1], at any depth."""
    right, up = Vector(right).normalized(), Vector(up).normalized()
    back = right.cross(up)
    eye = back * 50.0
    view = [*right, -right.dot(eye), *up, -up.dot(eye), *back, -back.dot(eye), 0, 0, 0, 1]
    near, far = 1.0, 100.0
    s = 1 / half_size
    projection = [s, 0, 0, 0, 0, s, 0, 0, 0, 0, -2 / (far - near), -(far + near) / (far - near), 0, 0, 0, 1]
    to_px = lambda v: (v * s + 1) / 2 * TOP_VIEW_SIZE  # noqa: E731
    return {"view": view, "projection": projection, "viewport": [TOP_VIEW_SIZE, TOP_VIEW_SIZE],
            "rect": [to_px(x0), to_px(y0), to_px(x1), to_px(y1)], "objects": objects, "negative": negative,
            "time_window": window, "after": after, "swept": swept}


def top_box(x0, y0, x1, y1, objects, *, half_size=6.0, negative=False, window=None, after=None, turned=False,
            swept=False):
    """A goal box seen from straight above, the view turned 45° about the vertical when `turned`."""
    c = math.sqrt(0.5)
    right, up = ((c, c, 0), (-c, c, 0)) if turned else ((1, 0, 0), (0, 1, 0))
    return ortho_box(right, up, x0, y0, x1, y1, objects, half_size=half_size, negative=negative, window=window,
                     after=after, swept=swept)


def last_second():
    """The time window of the scene's last second."""
    end = bpy.context.scene.frame_end / bpy.context.scene.render.fps
    return [end - 1.0, end]


def fraction_box(fractions, objects, window):
    """A goal box over a fraction (x0, y0, x1, y1) of the scene camera's view."""
    view, projection, (width, height) = cli.camera_view(bpy.context.scene.camera.name)
    x0, y0, x1, y1 = fractions
    return {"view": np.asarray(view).ravel().tolist(), "projection": np.asarray(projection).ravel().tolist(),
            "viewport": [width, height], "rect": [x0 * width, y0 * height, x1 * width, y1 * height],
            "objects": objects, "negative": False, "time_window": window, "after": None, "swept": False}


def quickstart_goal():
    """The marble in the left bin, the cone in the middle one and the pill in the right one, over
    the last second (together about one world in a hundred; with quickstart_orientations, 2 of
    10,000 fresh worlds)."""
    return [fraction_box((0.32, 0.22, 0.38, 0.40), ["Marble"], [3.0, 4.0]),
            fraction_box((0.40, 0.19, 0.46, 0.37), ["Cone"], [3.0, 4.0]),
            fraction_box((0.50, 0.15, 0.557, 0.33), ["Pill"], [3.0, 4.0])]


def marble_run_goal():
    """The marble tips every cup in turn, the way the run zigzags (Cup1 right, Cup2 left, ...: each
    pours it onto the chute below it, towards the next cup), and ends in the basket."""
    boxes = []
    count = sum(1 for o in bpy.data.objects if o.name.startswith("Cup") and o.name[3:].isdigit())
    cups = [(f"Cup{k}", +1 if k % 2 else -1) for k in range(1, count + 1)]
    for k, (cup, side) in enumerate(cups):
        hinge = bpy.data.objects[f"{cup}Hinge"].matrix_world.translation
        # On the chute under the rim it must tip over: 10 to 35 cm beyond the hinge, below the cup.
        x_near, x_far = hinge.x + side * 0.10, hinge.x + side * 0.35
        points = [Vector((x, 0, z)) for x in (x_near, x_far) for z in (hinge.z - 0.32, hinge.z - 0.12)]
        boxes.append(camera_box(points, ["Marble"], after=k - 1 if k else None))
    basket = [n for n in (o.name for o in bpy.data.objects) if n.startswith("GoalBasket")]
    boxes.append(camera_box(corners(basket, lift=0.15), ["Marble"], window=last_second(), after=len(cups) - 1))
    return boxes


def pachinko_letters_goal():
    """Every letter in its own slot over the last second."""
    return [camera_box(corners([f"Slot{i}_{c}"], lift=0.5), [f"Letter{i}_{c}"], window=[5.0, 6.0])
            for i, c in enumerate("WORLDS", 1)]


def siggraph_letters_goal():
    """Every letter in its own slot over the last second (the word started reversed)."""
    return [camera_box(corners([f"Slot{i}_{c}"], lift=0.5), [f"Letter{i}_{c}"], window=last_second())
            for i, c in enumerate("SIGGRAPH", 1)]


def siggraph_upright_orientations():
    """With siggraph_letters_goal: every letter upright in its slot over the last second, its own
    up within 20° of straight up. A letter's glyph is drawn in its local XZ plane with the top of
    the letter towards local +Z (blend_examples/peg_board.py), and every letter starts upright."""
    return [{"objects": [f"Letter{i}_{c}"], "axis": [0, 0, 1], "target": [0, 0, 1], "within_deg": 20,
             "time_window": last_second()} for i, c in enumerate("SIGGRAPH", 1)]


# The die's own axis each number faces along (blend_examples/dice/build_dice.py).
DIE_FACE_AXES = {1: [0, 0, -1], 2: [0, -1, 0], 3: [-1, 0, 0], 4: [1, 0, 0], 5: [0, 1, 0], 6: [0, 0, 1]}


def dice_goal():
    """No boxes: the dice goal is all pose parts (dice_orientations)."""
    return []


def dice_orientations():
    """Die1 shows one, Die2 two, ... Die5 five over the last second: each die's own axis for its
    number within 20° of straight up (about 1 in 8,000 fresh worlds; each part alone about 1 in 6)."""
    return [{"objects": [f"Die{k}"], "axis": DIE_FACE_AXES[k], "target": [0, 0, 1], "within_deg": 20,
             "time_window": last_second()} for k in range(1, 6)]


PARTS = ["Pelvis", "Torso", "Head", "UpperArmL", "UpperArmR", "ForearmL", "ForearmR", "ThighL", "ThighR",
         "ShinL", "ShinR"]


def spiral_staircase_goal():
    """The paper's full goal: he falls from top to bottom without leaving the staircase's footprint,
    ends on one of the last two treads, and does not slide down on his back.
    - Negative boxes on every body part all round the footprint seen from above (two square frames,
      one turned 45°: an octagon 15 cm outside the treads).
    - Positive boxes on the Pelvis over every fourth step on the way, in turn (each seen side-on
      across its tread, from the tread up to 0.7 m above it).
    - At the end (the last second), the Pelvis over the last two treads, within 0.7 m above them.
    - An orientation part: his torso's front (its local +Y) is never within 45° of straight up for
      more than 2 s (lying or sliding on his back; a tumble through that pose is brief)."""
    steps = sorted((o for o in bpy.data.objects if o.name.startswith("Step")), key=lambda o: o.name)
    r = max(Vector(((s.matrix_world @ Vector(c)).x, (s.matrix_world @ Vector(c)).y)).length
            for s in steps for c in s.bound_box) + 0.15
    big = 6.0
    frame = [(-big, -big, -r, big), (r, -big, big, big), (-r, -big, r, -r), (-r, r, r, big)]
    boxes = [top_box(*rect, PARTS, negative=True, turned=turned) for turned in (False, True) for rect in frame]

    def tread_top(step):
        return max((step.matrix_world @ Vector(c)).z for c in step.bound_box)

    def side_on(radial, half_width, z_low, z_high, **kw):
        """A box seen side-on across the radial line `radial` (a horizontal direction from the
        axis): half_width metres either side of it, heights z_low to z_high."""
        radial = Vector((radial.x, radial.y, 0)).normalized()
        return ortho_box((-radial.y, radial.x, 0), (0, 0, 1), -half_width, z_low, half_width, z_high, ["Pelvis"],
                         half_size=max(6.0, z_high + 1.0), **kw)

    def radial_of(*on_steps):
        return sum((Vector((s.matrix_world.translation.x, s.matrix_world.translation.y, 0)).normalized()
                    for s in on_steps), Vector())

    for k in range(3, len(steps) - 4, 4):
        top = tread_top(steps[k])
        boxes.append(side_on(radial_of(steps[k]), 0.35, top - 0.1, top + 0.7,
                             after=len(boxes) - 1 if k > 3 else None))
    # At the end: over the last two treads (half a tread's width either side of the line between
    # them at the walking line), from the lower tread up to 0.7 m above the upper one.
    boxes.append(side_on(radial_of(steps[-1], steps[-2]), 0.3, tread_top(steps[-1]) - 0.1, tread_top(steps[-2]) + 0.7,
                         window=last_second(), after=len(boxes) - 1))
    return boxes


def spiral_staircase_orientations():
    return [{"objects": ["Torso"], "axis": [0, 1, 0], "target": [0, 0, 1], "within_deg": 45, "negative": True,
             "longer_than_s": 2.0}]


def trebuchet_tower_goal():
    """The paper's queries, on the shot they are for: the rock hits the tower (a swept box over the
    tower: the rock's shape, not its centre, must reach it while it flies in); it brings the top of
    the tower down (a block of the top layer lies on the ground behind the tower in the last
    second); and no falling block touches a bystander (swept negative boxes on every block over
    each bystander's own footprint seen from above, so a block whose shape reaches a bystander's,
    side-on or from above, fails the goal). Two bystanders stand behind the tower, where its top
    lands."""
    blocks = [o.name for o in bpy.data.objects if o.name.startswith("Block")]
    boxes = [camera_box(corners(blocks), ["Rock"], window=[2.5, 4.5], swept=True)]
    # Seen side-on along the throw (+X): every depth, beyond the tower's back face, below 0.6 m
    # (a 0.25 m block lying on the ground, or on another fallen one).
    top_layer = max(bpy.data.objects[b].location.z for b in blocks)
    top = [b for b in blocks if bpy.data.objects[b].location.z > top_layer - 0.01]
    back = max((bpy.data.objects[b].matrix_world @ Vector(c)).x for b in blocks for c in bpy.data.objects[b].bound_box)
    boxes.append(ortho_box((1, 0, 0), (0, 0, 1), back + 0.25, -1.0, back + 10.0, 0.6, top, half_size=20.0,
                           window=last_second()))
    # Seen from above, so the tower behind a bystander is not in its box.
    for k in (1, 2, 3):
        ob = bpy.data.objects[f"Bystander{k}"]
        xs = [(ob.matrix_world @ Vector(c)).x for c in ob.bound_box]
        ys = [(ob.matrix_world @ Vector(c)).y for c in ob.bound_box]
        boxes.append(top_box(min(xs), min(ys), max(xs), max(ys), blocks, half_size=20.0, negative=True, swept=True))
    return boxes


def quickstart_orientations():
    """The cone stands in its bin (within 15° of upright) and the die shows its top face (its
    local up within 10° of up), over the last second."""
    return [{"objects": ["Cone"], "within_deg": 15, "time_window": [3.0, 4.0]},
            {"objects": ["Die"], "within_deg": 10, "time_window": [3.0, 4.0]}]


# Each goal's boxes, and its parts that test orientation beside them (GoalJson.h's "orientations").
GOALS = {"quickstart": quickstart_goal, "marble_run": marble_run_goal, "pachinko_letters": pachinko_letters_goal,
         "siggraph_letters": siggraph_letters_goal, "siggraph_upright": siggraph_letters_goal,
         "spiral_staircase": spiral_staircase_goal, "trebuchet_tower": trebuchet_tower_goal, "dice": dice_goal}
ORIENTATIONS = {"quickstart": quickstart_orientations, "spiral_staircase": spiral_staircase_orientations,
                "siggraph_upright": siggraph_upright_orientations, "dice": dice_orientations}
# The example a goal is on, where the goal is not named after it.
EXAMPLE_OF = {"siggraph_upright": "siggraph_letters"}


def engine(*args):
    result = subprocess.run([paths.engine_path(), *args], capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(f"engine failed: {result.stderr.strip()}")
    return result.stdout


def query_parts(goal, orientations, library):
    """The goal as the browser's own query: its boxes, then its orientation parts as pose parts,
    in the goal file's order. A module without pose parts (`_native.pose_part`) leaves them out:
    the query then asks less than the goal, and nothing at all of a goal without boxes."""
    names = list(_native.Scene.from_json(library.scene_json).body_objects)

    def bodies(part):
        return [i for i, n in enumerate(names) if n in part["objects"]]

    def window(part):
        return tuple(part["time_window"]) if part.get("time_window") else None

    def after(part):
        return -1 if part.get("after") is None else part["after"]

    parts = [_native.QueryBox(np.asarray(b["view"]).reshape(4, 4), np.asarray(b["projection"]).reshape(4, 4),
                              tuple(b["viewport"]), tuple(b["rect"]), negative=b["negative"], bodies=bodies(b),
                              time_window=window(b), swept=b.get("swept", False), after=after(b)) for b in goal]
    if hasattr(_native, "pose_part"):
        parts += [_native.pose_part(bodies=bodies(o), within_deg=o["within_deg"], axis=tuple(o.get("axis", (0, 0, 1))),
                                    target=tuple(o.get("target", (0, 0, 1))), negative=o.get("negative", False),
                                    longer_than_s=o.get("longer_than_s", 0.0), time_window=window(o), after=after(o))
                  for o in orientations]
    return parts


def refinement_effects(parts, library, index):
    """Of the worlds refinement made, how many lost a part of the browser's query (query_parts)
    their parent met, and how many meet more of them than it: (children, lost, gained), or None
    when the query holds no parts. `index` holds every world of `library`."""
    if not parts:
        return None
    met = {}

    def met_of(world):
        if world not in met:
            met[world] = list(index.score(world, parts).met)
        return met[world]

    children = lost = gained = 0
    for world in (int(w) for w in library.world_indices):
        parent = library.world_info(world).parent_world
        if parent < 0:
            continue
        child, before = met_of(world), met_of(parent)
        children += 1
        lost += any(was and not now for was, now in zip(before, child))
        gained += sum(child) > sum(before)
    return children, lost, gained


def goal_matches(goal, orientations, goal_path, library_path):
    """The worlds of the library that meet the goal, every part as the search scores them; each
    must meet the browser's own query too (query_parts; skipped when it holds no parts). Returns
    the library, the browser's path index of all its worlds, the query's parts and those worlds."""
    library = _native.Library(library_path)
    index = _native.PathIndex(_native.body_bounding_radii(_native.Scene.from_json(library.scene_json)))
    index.add_library(library)
    parts = query_parts(goal, orientations, library)
    with open(goal_path) as f:
        by_search = set(int(w) for w in _native.worlds_meeting_goal(library_path, f.read()))
    if parts:
        by_browser = set(int(w) for w in index.query(parts).matching)
        if not by_search <= by_browser:
            raise SystemExit(f"worlds {sorted(by_search - by_browser)} meet the goal as searched but not the "
                             f"browser's query")
    return library, index, parts, by_search


def search_from(seed, scene_json, goal_path, goal, orientations, folder):
    """Sample the first batch of base seed `seed`, then seek. Returns a dict of what happened."""
    library_path = os.path.join(folder, f"seed{seed}.mwb")
    if os.path.exists(library_path):
        os.remove(library_path)
    start = time.perf_counter()
    engine("sample", "--scene", scene_json, "--out", library_path, "--worlds", f"0:{FIRST_BATCH}", "--seed", str(seed))
    sampled_s = time.perf_counter() - start
    _, _, _, first_met = goal_matches(goal, orientations, goal_path, library_path)
    out = engine("seek", "--library", library_path, "--goal", goal_path, "--want", "1", "--seed", str(seed),
                 "--budget-worlds", str(BUDGET_WORLDS), "--budget-s", str(max(1.0, BUDGET_S - sampled_s)), "--json")
    elapsed = time.perf_counter() - start
    outcome = json.loads(out.strip().splitlines()[-1])
    library, index, parts, matching = goal_matches(goal, orientations, goal_path, library_path)
    reached = bool(outcome["reached"]) and all(w in matching for w in outcome["found"])
    lineage = len(library.world_info(outcome["best"]).lineage) if outcome["best"] in set(
        int(w) for w in library.world_indices) else 0
    effects = refinement_effects(parts, library, index)
    children, lost, gained = effects if effects is not None else (0, 0, 0)
    return {"seed": seed, "first_met": len(first_met), "reached": reached, "worlds": FIRST_BATCH + outcome["worlds_made"],
            "s": elapsed, "best": outcome["best"], "best_boxes_met": outcome["best_boxes_met"], "boxes": outcome["boxes"],
            "refinements": outcome["refinements"], "lineage": lineage, "children": children, "lost": lost,
            "gained": gained, "scored": effects is not None}


def percent(part, whole, sign="%"):
    return f"{100 * part / whole:.1f}{sign}" if whole else "n/a"


def main():
    example = os.path.splitext(os.path.basename(bpy.data.filepath))[0]
    name = GOAL_NAME or example
    if name not in GOALS:
        raise SystemExit(f"no goal {name} (have: {', '.join(GOALS)})")
    if EXAMPLE_OF.get(name, name) != example:
        raise SystemExit(f"goal {name} is on {EXAMPLE_OF.get(name, name)}.blend, not {example}.blend")
    many_worlds.register()
    result, problems = export_and_validate(bpy.context)
    if result.scene is None or problems:
        raise SystemExit(f"{name}: cannot export: {problems}")
    goal, orientations = GOALS[name](), ORIENTATIONS.get(name, lambda: [])()
    # MWB_SEEK_KEEP=DIR keeps the scene, goal and libraries there for a closer look.
    keep = os.environ.get("MWB_SEEK_KEEP")
    if keep:
        os.makedirs(keep, exist_ok=True)
    runs = []
    with contextlib.nullcontext(keep) if keep else tempfile.TemporaryDirectory() as folder:
        scene_json, goal_path = (os.path.join(folder, f) for f in ("scene.json", "goal.json"))
        with open(scene_json, "w") as f:
            f.write(result.to_json())
        with open(goal_path, "w") as f:
            json.dump({"boxes": goal, "orientations": orientations}, f)
        if BATCHES == 0:
            # Only the scene and the goal, for a closer look at them (MWB_SEEK_KEEP).
            print(f"{name}: scene and goal in {folder}")
            return
        for seed in SEEDS:
            run = search_from(seed, scene_json, goal_path, goal, orientations, folder)
            runs.append(run)
            effects = (f"of its {run['children']} refined worlds {percent(run['lost'], run['children'])} lost a "
                       f"part their parent met, {percent(run['gained'], run['children'])} met more parts"
                       if run["scored"] else "the browser's query holds none of its parts")
            print(f"{name} seed {seed}: {run['first_met']} of the first {FIRST_BATCH} worlds meet the goal; "
                  f"{'reached' if run['reached'] else 'not reached'}: best world {run['best']} meets "
                  f"{run['best_boxes_met']} of {run['boxes']} goal parts ({run['lineage']} refinements deep), "
                  f"{run['worlds']} worlds, {run['refinements']} refine calls, {run['s']:.1f} s; {effects}",
                  flush=True)
    worlds = sorted(r["worlds"] for r in runs)
    seconds = sorted(r["s"] for r in runs)
    reached = sum(r["reached"] for r in runs)
    first_met = sum(r["first_met"] for r in runs)
    median = len(runs) // 2
    print(f"{name}: reached from {reached} of {len(runs)} first batches ({first_met} first-batch worlds met it "
          f"already); worlds median {worlds[median]}, worst {worlds[-1]}; time median {seconds[median]:.1f} s, "
          f"worst {seconds[-1]:.1f} s")
    print(f"BENCH seek_{name}_first_batch_met {first_met}")
    print(f"BENCH seek_{name}_reached {reached}")
    print(f"BENCH seek_{name}_worlds {worlds[median]}")
    print(f"BENCH seek_{name}_s {seconds[median]:.1f}")
    print(f"BENCH seek_{name}_worst_worlds {worlds[-1]}")
    print(f"BENCH seek_{name}_worst_s {seconds[-1]:.1f}")
    # Why a search stalls: refined worlds losing what their parent had, and how few gain.
    children = sum(r["children"] for r in runs)
    if children:
        print(f"BENCH seek_{name}_children_losing_met_pct {percent(sum(r['lost'] for r in runs), children, '')}")
        print(f"BENCH seek_{name}_children_gaining_pct {percent(sum(r['gained'] for r in runs), children, '')}")


main()
