"""Headless command line: sample, merge, inspect, query, rank, bake and preview libraries.

    blender -b FILE.blend --python-exit-code 1 --python addon/many_worlds/cli.py -- COMMAND [options]
    blender -c many_worlds COMMAND [options]          (the installed extension, Blender 4.2+)

With `-c` no .blend is open: `sample FILE.blend` opens it, and the other commands that read the
scene take `--blend FILE.blend`.

Commands (run `... -- help` for the options):
    sample   sample worlds of the open .blend into a library (the engine runs as a child process)
    merge    merge libraries of one run into a new one
    info     worlds, bodies, sizes, rejections and the scene hash of a library
    query    worlds whose paths enter (or avoid) boxes drawn in the scene camera's view, and whose
             objects hold (or avoid) poses
    rank     worlds sorted by a metric
    seek     refine a library's worlds until some meet every box and pose (the engine runs as a child
             process)
    bake     write one world as keyframes and save the result as a new .blend
    preview  a contact sheet PNG of chosen worlds: the scene rendered from its camera at each world's
             last frame, the paths over it, a legend of the objects' colours

A user mistake prints one line starting with "many_worlds: error:" and exits with status 2.
"""
import argparse
import json
import os
import re
import signal
import sys
import tempfile
import time

if __name__ == "__main__":
    # Run as a script by Blender: make the package importable from this checkout and resolve the
    # relative imports below in it (PEP 366). They are relative because the installed extension's
    # package is `bl_ext.<repository>.many_worlds`, where `import many_worlds` fails.
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    __package__ = "many_worlds"

import numpy as np  # noqa: E402

from . import _native  # noqa: E402
from .core import contact_sheet, engine, export_warnings, goal, palette, paths, pose_target  # noqa: E402
from .core.progress_printer import ProgressPrinter  # noqa: E402
from .core.library_view import LibraryView  # noqa: E402
from .core.library_query import BOXES_MET, BoxSpec, LibraryQuery, PoseSpec, metric_name  # noqa: E402

METRICS = tuple(m.name for m in _native.ranking_metrics())


class CliError(Exception):
    """A user mistake: reported on one line, never as a traceback."""


def parse_range(text, what):
    """'N' is worlds 0..N-1; 'A:B' is worlds A..B-1."""
    try:
        if ":" in text:
            a, b = (int(v) for v in text.split(":"))
        else:
            a, b = 0, int(text)
    except ValueError:
        raise CliError(f"{what}: expected N or A:B, got '{text}'")
    if a < 0 or b <= a:
        raise CliError(f"{what}: empty or negative range '{text}'")
    return a, b


def parse_numbers(text, count, what):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise CliError(f"{what}: expected {count} comma-separated numbers, got '{text}'")
    if len(values) != count:
        raise CliError(f"{what}: expected {count} comma-separated numbers, got '{text}'")
    return values


def require_file(path, what="file"):
    if not os.path.isfile(path):
        raise CliError(f"{what} not found: {path}")
    return path


def open_view(path):
    """The library as the add-on browses it: the bodies of its current scene, which exist where."""
    require_file(path, "library")
    try:
        return LibraryView(_native, path)
    except _native.LibraryError as error:
        raise CliError(str(error))


def check_library_matches_scene(view, path):
    """The library must come from this .blend: every body it holds is an object here, except bodies
    that some worlds lack (added or removed after sampling; a removed one may be deleted here)."""
    import bpy
    names = view.body_names
    missing = [i for i, name in enumerate(names) if name not in bpy.data.objects]
    if missing:
        lacking = set()
        for world in view.library.world_indices:
            lacking.update(i for i, present in enumerate(view.library.present(world)) if not present)
        missing = [i for i in missing if i not in lacking]
    if missing:
        raise CliError(f"{path} was sampled from another scene: no object {names[missing[0]]!r} in "
                       f"{bpy.data.filepath or 'this file'}")


def body_indices(view, objects_text):
    """The body indices of the objects named (comma-separated), or every simulated body."""
    names = view.body_names
    if objects_text:
        wanted = [n.strip() for n in objects_text.split(",") if n.strip()]
        unknown = [n for n in wanted if n not in names]
        if unknown:
            raise CliError(f"unknown object {unknown[0]!r} (the library has: {', '.join(names)})")
        return [i for i, name in enumerate(names) if name in wanted]
    return view.simulated_bodies()


# --- sample ---------------------------------------------------------------------------------

def command_sample(args):
    import bpy
    from . import sample_setup
    if args.seeds and args.worlds:
        raise CliError("give --worlds or --seeds, not both")
    settings = getattr(bpy.context.scene, "mwb", None)
    first, end = parse_range(args.seeds or args.worlds or str(getattr(settings, "world_count", 100)),
                             "--seeds" if args.seeds else "--worlds")
    out = os.path.abspath(args.out)
    # The same path as the Sample button: the scene's run settings, --seed and --duration on top.
    try:
        request, warnings = sample_setup.sample_request(bpy.context, out, first, end - first, args.threads,
                                                seed=args.seed, duration_s=args.duration)
    except sample_setup.RunSetupError as error:
        raise CliError(str(error)[0].lower() + str(error)[1:])
    constraints = {ob.name for ob in bpy.context.scene.objects if ob.rigid_body_constraint is not None}
    shown = warnings if args.all_warnings else export_warnings.grouped_warning_lines(warnings, constraints=constraints)
    for line in shown:
        print(f"many_worlds: warning: {line}", file=sys.stderr)
    if len(shown) < len(warnings):
        print(f"many_worlds: {len(warnings)} warnings in all (--all-warnings lists each)", file=sys.stderr)

    def progress_words(run):
        done, total, _ = run.progress()
        return f"sampled {done}/{total} worlds" if total else None

    return follow_engine(request, progress_words)


def follow_engine(request, progress_words, json_summary=False, poll_s=0.1):
    """Run the engine on `request` to its end: its progress as `progress_words(run)` puts it (None:
    nothing to say yet), the lines it prints besides its events passed on, then its summary (its
    fields as one JSON object with `json_summary`, else its text).
    Ctrl-C asks it to stop (it keeps every finished world and exits with EngineExit.CANCELLED).
    Returns the exit status; raises CliError with the engine's own message when it fails."""
    try:
        run = engine.EngineProcess(request)
    except FileNotFoundError as error:
        raise CliError(str(error))
    previous = signal.signal(signal.SIGINT, lambda *_: run.cancel())
    # One line rewritten in place on a terminal; in a log, one every few seconds and the last.
    progress = ProgressPrinter(sys.stderr)
    shown_words, shown_log = None, 0

    def show():
        nonlocal shown_words, shown_log
        log = run.log()
        if len(log) > shown_log:
            progress.interrupt()
            for line in log[shown_log:]:
                print(line, file=sys.stderr)
            shown_log = len(log)
        words = progress_words(run)
        if words and words != shown_words:
            progress.update(f"many_worlds: {words}")
            shown_words = words

    try:
        while not run.finished():
            show()
            time.sleep(poll_s)
        run.wait()
        show()
    finally:
        progress.finish()
        # Blender installs its own handler from C, which Python reports as None.
        signal.signal(signal.SIGINT, previous if previous is not None else signal.SIG_DFL)
    failed = run.failure()
    if failed is not None:
        raise CliError(failed.message)
    for warning in run.warnings():
        print(f"many_worlds: engine: warning: {warning}", file=sys.stderr)
    summary = run.summary()
    if summary is not None:
        text = summary.pop("text")
        print(json.dumps(summary, separators=(",", ":")) if json_summary else text.strip())
    if run.returncode() == int(engine.EngineExit.CANCELLED):
        print("many_worlds: interrupted; finished worlds are kept", file=sys.stderr)
        return int(engine.EngineExit.CANCELLED)
    return 0


# --- merge and info -------------------------------------------------------------------------

def command_merge(args):
    for path in args.inputs:
        require_file(path, "library")
    if os.path.exists(args.output):
        if not args.overwrite:
            raise CliError(f"{args.output} exists (use --overwrite to replace it)")
        os.remove(args.output)
    try:
        warnings = _native.merge_libraries(args.inputs, args.output)
    except _native.LibraryError as error:
        raise CliError(str(error).replace("\n", " "))
    for warning in warnings:
        print(f"many_worlds: warning: {warning}", file=sys.stderr)
    print(f"merged {len(args.inputs)} libraries: {len(_native.Library(args.output, 0).world_indices)} worlds -> {args.output}")
    return 0


def command_info(args):
    require_file(args.library, "library")
    try:
        run = engine.run_to_end(engine.InfoRequest(args.library, as_json=args.json))
    except FileNotFoundError as error:
        raise CliError(str(error))
    failed = run.failure()
    if failed is not None:
        raise CliError(failed.message)
    print(run.summary()["text"].rstrip())
    return 0


# --- query and rank -------------------------------------------------------------------------

def camera_view(name):
    """(view, projection, (width, height)) of a camera object, at the render resolution."""
    import bpy
    camera = bpy.data.objects.get(name)
    if camera is None or camera.type != "CAMERA":
        cameras = [o.name for o in bpy.data.objects if o.type == "CAMERA"]
        raise CliError(f"no camera {name!r} (cameras here: {', '.join(cameras) or 'none'})")
    render = bpy.context.scene.render
    width = render.resolution_x * render.resolution_percentage / 100
    height = render.resolution_y * render.resolution_percentage / 100
    projection = camera.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=int(width), y=int(height),
                                           scale_x=render.pixel_aspect_x, scale_y=render.pixel_aspect_y)
    return np.array(camera.matrix_world.inverted()), np.array(projection), (width, height)


def parse_after(text):
    """--after N: N counts the --box and --pose groups from 1 in command-line order. Returns the
    0-based position (whether that part exists is the goal's rule, checked with the goal)."""
    try:
        after = int(text)
    except ValueError:
        raise CliError(f"--after: expected a part number, got '{text}'")
    if after < 1:
        raise CliError(f"--after {text}: parts are numbered from 1")
    return after - 1


def parse_window(spec):
    return tuple(parse_numbers(spec["time"], 2, "--time")) if spec.get("time") else None


def object_rotation(name, frame):
    """The 3x3 world rotation of object `name` at `frame` of the open scene (scale removed)."""
    import bpy
    scene = bpy.context.scene
    current = scene.frame_current
    try:
        scene.frame_set(frame)
        return np.array(bpy.data.objects[name].matrix_world.to_quaternion().to_matrix())
    finally:
        scene.frame_set(current)


def pose_spec(spec, view, after):
    """The PoseSpec of a --pose group."""
    bodies = body_indices(view, spec["pose"])
    if spec.get("within") is None:
        raise CliError(f"--pose {spec['pose']}: give its tolerance with --within DEG")
    try:
        within = float(spec["within"])
    except ValueError:
        raise CliError(f"--within: expected degrees, got '{spec['within']}'")
    axis = tuple(parse_numbers(spec["axis"], 3, "--axis")) if spec.get("axis") else None
    target = tuple(parse_numbers(spec["target"], 3, "--target")) if spec.get("target") else (0.0, 0.0, 1.0)
    if spec.get("as_posed") is not None:
        if spec.get("target"):
            raise CliError("--as-posed and --target both give the direction: use one")
        names = [view.body_names[b] for b in bodies]
        if len(names) != 1:
            raise CliError(f"--as-posed: name one object per --pose (each keeps its own pose), got {', '.join(names)}")
        try:
            frame = int(spec["as_posed"])
        except ValueError:
            raise CliError(f"--as-posed: expected a frame number, got '{spec['as_posed']}'")
        rotation = object_rotation(names[0], frame)
        if axis is None:
            # The side that faces up at that frame stays up.
            axis, target = pose_target.captured_axis(rotation), pose_target.UP
        else:
            target = tuple(float(v) for v in rotation @ np.asarray(axis))
    longer = 0.0
    if spec.get("longer_than") is not None:
        if not spec.get("negative"):
            raise CliError("--longer-than applies to a --negative pose: how long it may be held")
        try:
            longer = float(spec["longer_than"])
        except ValueError:
            raise CliError(f"--longer-than: expected seconds, got '{spec['longer_than']}'")
    return PoseSpec(bodies=tuple(bodies), within_deg=within, axis=axis or (0.0, 0.0, 1.0), target=target,
                    negative=spec.get("negative", False), longer_than_s=longer, time_window=parse_window(spec),
                    after=after)


def goal_specs(args, view):
    """The --box and --pose groups as BoxSpecs (in the camera's view, pixels at the render
    resolution) and PoseSpecs, in command-line order."""
    parts = args.goal_parts
    camera = None
    specs = []
    for k, spec in enumerate(parts):
        after = parse_after(spec["after"]) if spec.get("after") is not None else -1
        if "pose" in spec:
            specs.append(pose_spec(spec, view, after))
            continue
        x0, y0, x1, y1 = parse_numbers(spec["box"], 4, "--box")
        if not all(0 <= v <= 1 for v in (x0, y0, x1, y1)):
            raise CliError(f"--box: coordinates are fractions of the camera view in [0, 1], got '{spec['box']}'")
        if camera is None:
            camera = camera_view(args.camera)
        view_matrix, projection, (width, height) = camera
        specs.append(BoxSpec(view=view_matrix, projection=projection, size=(width, height),
                             rect=(x0 * width, y0 * height, x1 * width, y1 * height),
                             negative=spec.get("negative", False),
                             bodies=tuple(body_indices(view, spec.get("objects") or getattr(args, "objects", None))),
                             time_window=parse_window(spec), swept=spec.get("swept", False), after=after))
    return specs


def evaluate_goal(args, view):
    """(LibraryQuery over every world, Matches of the --box and --pose groups, or None
    without any). Like the add-on, a part never sees bodies a world lacks."""
    specs = goal_specs(args, view)
    lq = LibraryQuery(_native, view)
    if not specs:
        return lq, None
    try:
        return lq, lq.evaluate(specs)
    except ValueError as error:
        raise CliError(str(error))


def command_query(args):
    view = open_view(args.library)
    check_library_matches_scene(view, args.library)
    if not args.goal_parts:
        raise CliError("query needs at least one --box or --pose")
    _, result = evaluate_goal(args, view)
    matching = sorted(int(w) for w, m in zip(view.world_indices, result.matching) if m)
    if args.json:
        print(json.dumps({"worlds": len(view.world_indices), "matching": matching}))
    else:
        print(f"{len(matching)} of {len(view.world_indices)} worlds match")
        for w in matching:
            print(w)
    return 0


def command_rank(args):
    view = open_view(args.library)
    args.metric = metric_name(args.metric)
    if args.metric not in METRICS:
        raise CliError(f"unknown metric {args.metric!r} (one of: {', '.join(METRICS)})")
    bodies = body_indices(view, args.objects)
    if args.goal_parts:
        check_library_matches_scene(view, args.library)
    lq, result = evaluate_goal(args, view)
    if args.metric == BOXES_MET:
        if result is None:
            raise CliError("boxes_met counts the goal's parts: give at least one --box or --pose")
        ids, values = lq.rank(BOXES_MET, bodies, descending=not args.asc)
    else:
        # Without boxes every world matches; with them, only the matching worlds are ranked.
        ids, values = lq.rank(args.metric, bodies, combine=args.combine, descending=args.desc)
    limit = args.limit or len(ids)
    for w, v in list(zip(ids, values))[:limit]:
        print(f"{int(w)} {v:.6g}")
    return 0


# --- seek ---------------------------------------------------------------------------------

def command_seek(args):
    if not args.goal_parts:
        raise CliError("seek needs at least one --box or --pose (the goal)")
    for option, value in (("--want", args.want), ("--budget", args.budget)):
        if value < 1:
            raise CliError(f"{option}: expected at least 1, got {value}")
    if args.budget_s is not None and args.budget_s <= 0:
        raise CliError(f"--budget-s: expected a positive number of seconds, got {args.budget_s}")
    view = open_view(args.library)
    check_library_matches_scene(view, args.library)
    specs = goal_specs(args, view)
    with tempfile.TemporaryDirectory(prefix="mwb-seek-") as folder:
        try:
            goal_path = goal.write_goal(os.path.join(folder, "goal.json"), specs)
        except ValueError as error:
            raise CliError(str(error))
        request = engine.SeekRequest(os.path.abspath(args.library), goal_path, args.want, args.budget,
                                     args.budget_s or 0.0, args.seed, args.threads or 0)

        def progress_words(run):
            progress = run.seek_progress()
            return progress.text if progress else None

        return follow_engine(request, progress_words, json_summary=args.json)


# --- bake and preview -----------------------------------------------------------------------

def command_bake(args):
    import bpy
    from . import bake
    from .core.session import SESSION
    view = open_view(args.library)
    check_library_matches_scene(view, args.library)
    if args.world not in set(int(w) for w in view.world_indices):
        raise CliError(f"no world {args.world} in {args.library}")
    SESSION.view = view
    outcome = bake.bake_world(bpy.context, args.world)
    for warning in outcome.warnings:
        print(f"many_worlds: warning: {warning}", file=sys.stderr)
    out = os.path.abspath(args.out)
    bpy.ops.wm.save_as_mainfile(filepath=out, copy=True)
    print(f"{outcome.text(args.world)} -> {out}")
    return 0


def command_preview(args):
    import bpy
    from . import scene_render
    view = open_view(args.library)
    check_library_matches_scene(view, args.library)
    available = set(int(w) for w in view.world_indices)
    try:
        worlds = [int(w) for w in args.worlds.split(",")]
    except ValueError:
        raise CliError(f"--worlds: expected comma-separated world numbers, got '{args.worlds}'")
    missing = [w for w in worlds if w not in available]
    if missing:
        raise CliError(f"no world {missing[0]} in {args.library}")
    camera, projection, (width, height) = camera_view(args.camera)
    bodies = body_indices(view, args.objects)
    colours = palette.body_colours(view.body_names, view.simulated_bodies())
    tiles = []
    for w in worlds:
        polylines = view.library.polyline(w)
        tiles.append((w, [(polylines[b], palette.to_bytes(colours[b])) for b in view.present_bodies(w, bodies)]))
    legend = [(name, palette.to_bytes(colour)) for name, colour in palette.object_colours(
        view.body_names, view.simulated_bodies()).items() if any(view.body_names[b] == name for b in bodies)]
    backgrounds = None
    if args.engine != "none":
        engine, why = scene_render.choose_engine(args.engine)
        label = "Workbench" if engine == scene_render.WORKBENCH else "Cycles"
        print(f"many_worlds: rendering the scene with {label} ({why})", file=sys.stderr, flush=True)
        scene = bpy.context.scene
        scene.camera = bpy.data.objects[args.camera]
        tile_width, tile_height = contact_sheet.tile_size(args.tile_width, (width, height))
        backgrounds = scene_render.render_worlds(scene, view, worlds, tile_width, tile_height, engine)
    image = contact_sheet.render(tiles, camera, projection, (width, height), tile_width=args.tile_width,
                                 backgrounds=backgrounds, legend=legend)
    contact_sheet.save_png(image, os.path.abspath(args.out))
    print(f"contact sheet of {len(worlds)} worlds -> {os.path.abspath(args.out)}")
    return 0


# --- argument parsing -----------------------------------------------------------------------

# Options that say more of the last --box or --pose, and which of the two each applies to.
BOX_ONLY = {"--swept": "swept", "--objects": "objects"}
POSE_ONLY = {"--within": "within", "--axis": "axis", "--target": "target", "--as-posed": "as_posed",
             "--longer-than": "longer_than"}
EITHER = {"--negative": "negative", "--time": "time", "--after": "after"}


class GoalPartAction(argparse.Action):
    """Collects the repeatable --box and --pose groups in order; the options after one say more
    of it."""

    def __call__(self, parser, namespace, values, option_string=None):
        parts = getattr(namespace, "goal_parts", None) or []
        if option_string in ("--box", "--pose"):
            parts.append({option_string[2:]: values})
            namespace.goal_parts = parts
            return
        if not parts:
            raise argparse.ArgumentError(self, "comes before any --box or --pose")
        last = parts[-1]
        kind = "pose" if "pose" in last else "box"
        if option_string in BOX_ONLY and kind == "pose":
            raise argparse.ArgumentError(self, "applies to a --box, not to a --pose")
        if option_string in POSE_ONLY and kind == "box":
            raise argparse.ArgumentError(self, "applies to a --pose, not to a --box")
        key = {**BOX_ONLY, **POSE_ONLY, **EITHER}[option_string]
        last[key] = True if self.nargs == 0 else values


def add_goal_options(parser, objects_help=None):
    parser.set_defaults(goal_parts=[])
    parser.add_argument("--camera", default="Camera", help="camera the boxes are drawn in (default: Camera)")
    parser.add_argument("--box", action=GoalPartAction, metavar="X0,Y0,X1,Y1",
                        help="a box in camera-view fractions (0..1, origin bottom-left); repeatable")
    parser.add_argument("--swept", action=GoalPartAction, nargs=0, help="the last box tests whole bodies, not centres")
    if objects_help:
        parser.add_argument("--objects", action=GoalPartAction, metavar="A,B", help=objects_help)
    parser.add_argument("--pose", action=GoalPartAction, metavar="A,B",
                        help="a pose part: the objects named keep an axis within --within DEG of a direction; "
                             "repeatable")
    parser.add_argument("--within", action=GoalPartAction, metavar="DEG", help="the last pose's tolerance (degrees)")
    parser.add_argument("--axis", action=GoalPartAction, metavar="X,Y,Z",
                        help="the last pose's axis in the object's own frame (default: 0,0,1, its local up)")
    parser.add_argument("--target", action=GoalPartAction, metavar="X,Y,Z",
                        help="the world direction that axis should point (default: 0,0,1, up)")
    parser.add_argument("--as-posed", action=GoalPartAction, metavar="FRAME",
                        help="the last pose as the object is posed at FRAME: the side up then stays up "
                             "(with --axis: that axis keeps its direction at FRAME)")
    parser.add_argument("--longer-than", action=GoalPartAction, metavar="S",
                        help="a negative pose fails only when held longer than S seconds")
    parser.add_argument("--negative", action=GoalPartAction, nargs=0,
                        help="the last box rejects worlds entering it; the last pose, worlds holding it")
    parser.add_argument("--time", action=GoalPartAction, metavar="T0,T1",
                        help="the last box or pose applies between T0 and T1 s")
    parser.add_argument("--after", action=GoalPartAction, metavar="N",
                        help="the last part counts only when met after part N (--box and --pose numbered "
                             "from 1 in order)")


class Parser(argparse.ArgumentParser):
    # Values such as "-1,0,0" (--axis, --target) and "-0.5,2" are numbers, not options: argparse
    # reads a leading "-" as an option unless the text matches this.
    NEGATIVE_NUMBERS = re.compile(r"^-(\d+\.?\d*|\.\d+)(,-?(\d+\.?\d*|\.\d+))*$")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = self.NEGATIVE_NUMBERS

    def error(self, message):
        raise CliError(message)


def build_parser():
    parser = Parser(prog="many_worlds", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", parser_class=Parser)
    p = commands.add_parser("sample", help="sample worlds of the open .blend")
    p.add_argument("blend", nargs="?", help="the .blend to open first (default: the open one)")
    p.add_argument("--worlds", help="N (worlds 0..N-1) or A:B (worlds A..B-1); default: the scene's world count")
    p.add_argument("--seeds", help="A:B, the same as --worlds A:B")
    p.add_argument("--out", required=True, help="library file (.mwb); an existing one of the same run grows")
    p.add_argument("--threads", type=int, help="engine threads (default: the scene's Threads setting; 0: all cores)")
    p.add_argument("--duration", type=float, help="seconds per world (default: the frame range)")
    p.add_argument("--seed", type=int, help="base seed (default: the scene's)")
    p.add_argument("--all-warnings", action="store_true",
                   help="every export warning on its own line (default: one line per setting and reason)")
    p = commands.add_parser("merge", help="merge libraries of one run")
    p.add_argument("--overwrite", action="store_true", help="replace OUTPUT if it exists")
    p.add_argument("output")
    p.add_argument("inputs", nargs="+")
    p = commands.add_parser("info", help="describe a library")
    p.add_argument("library")
    p.add_argument("--json", action="store_true")
    p = commands.add_parser("query", help="worlds matching boxes in the camera view and poses")
    p.add_argument("library")
    p.add_argument("--blend", help="the .blend to open first (default: the open one)")
    p.add_argument("--json", action="store_true")
    add_goal_options(p, "objects the last box applies to (default: every simulated object)")
    p = commands.add_parser("rank", help="worlds sorted by a metric")
    p.add_argument("library")
    p.add_argument("--blend", help="the .blend to open first (default: the open one)")
    p.add_argument("--metric", required=True, help=", ".join(METRICS))
    p.add_argument("--combine", choices=("sum", "max"), default="sum")
    p.add_argument("--desc", action="store_true", help="largest first")
    p.add_argument("--asc", action="store_true", help="boxes_met: fewest parts met first")
    p.add_argument("--limit", type=int, help="print only the first N")
    p.add_argument("--objects", help="objects the metric combines and the boxes test (default: all simulated)")
    add_goal_options(p)
    p = commands.add_parser("seek", help="refine worlds until some meet every box and pose")
    p.add_argument("library")
    p.add_argument("--blend", help="the .blend to open first (default: the open one)")
    p.add_argument("--want", type=int, default=1, help="worlds meeting every part to find (default: 1)")
    p.add_argument("--budget", type=int, required=True, help="most worlds to make")
    p.add_argument("--budget-s", type=float, help="most seconds to run (default: no limit)")
    p.add_argument("--seed", type=int, help="seed of the refinements (default: the engine's)")
    p.add_argument("--threads", type=int, help="engine threads (default: all cores)")
    p.add_argument("--json", action="store_true", help="the summary as one JSON object")
    add_goal_options(p, "objects the last box applies to (default: every simulated object)")
    p = commands.add_parser("bake", help="bake one world to keyframes into a new .blend")
    p.add_argument("library")
    p.add_argument("--blend", help="the .blend to open first (default: the open one)")
    p.add_argument("--world", type=int, required=True)
    p.add_argument("--out", required=True)
    p = commands.add_parser("preview", help="contact sheet PNG of worlds: scene, paths and legend")
    p.add_argument("library")
    p.add_argument("--blend", help="the .blend to open first (default: the open one)")
    p.add_argument("--worlds", required=True, help="comma-separated world numbers")
    p.add_argument("--out", required=True)
    p.add_argument("--camera", default="Camera")
    p.add_argument("--objects", help="objects whose paths are drawn (default: every simulated object)")
    p.add_argument("--tile-width", type=int, default=320)
    p.add_argument("--engine", choices=("auto", "workbench", "cycles", "none"), default="auto",
                   help="renderer of the scene behind the paths (auto: Workbench with a GL context, "
                        "else Cycles; none: paths on a plain background)")
    commands.add_parser("help", help="show this help")
    return parser


COMMANDS = {"sample": command_sample, "merge": command_merge, "info": command_info, "query": command_query,
            "rank": command_rank, "seek": command_seek, "bake": command_bake, "preview": command_preview}


def ensure_registered():
    """Scene and object settings of the add-on are read through its registered properties."""
    import bpy
    if not hasattr(bpy.types.Scene, "mwb"):
        sys.modules[__package__].register()


def open_blend(args):
    """Opens the .blend a command names; one is needed when Blender was started without a file."""
    blend = getattr(args, "blend", None)
    if blend is None:
        return
    import bpy
    if not os.path.isfile(blend):
        raise CliError(f"{blend}: no such .blend file")
    bpy.ops.wm.open_mainfile(filepath=os.path.abspath(blend))


def main(argv):
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command in (None, "help"):
            parser.print_help()
            return 0 if args.command == "help" else 2
        open_blend(args)
        if args.command in ("sample", "bake"):
            ensure_registered()
        return COMMANDS[args.command](args)
    except CliError as error:
        print(f"many_worlds: error: {error}", file=sys.stderr)
        return 2
    except (_native.SceneError, _native.LibraryError, _native.CodecError, OSError) as error:
        print(f"many_worlds: error: {str(error).splitlines()[0]}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    sys.exit(main(arguments))
