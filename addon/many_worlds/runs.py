"""Where every sampling run starts: the Sample button, the command line and the farm tasks (which
run the command line) export the scene and read the scene's run settings here, and nowhere else,
so the same .blend and world range give the same library whichever way it was started."""
import os
import shutil
import subprocess

from . import export
from .core import engine as engine_process
from .core import paths


class RunSetupError(Exception):
    """The run cannot start; the message says why, in the user's words."""

    def __init__(self, message, problems=()):
        super().__init__(message)
        self.problems = list(problems)


def run_settings(scene, seed=None, duration_s=None):
    """The scene's run settings (Many Worlds sidebar) as a RunSettings; `seed` and `duration_s`
    override the scene's when given (the command line's --seed and --duration)."""
    settings = getattr(scene, "mwb", None)

    def setting(name, default):
        return getattr(settings, name, default) if settings is not None else default

    return engine_process.RunSettings(
        seed=int(seed if seed is not None else setting("seed", 0)),
        duration_s=float(duration_s if duration_s is not None else setting("duration_s", 0.0)),
        stop_at_rest=bool(setting("stop_at_rest", True)),
        alpha=float(setting("alpha", 0.1)),
        position_error_m=float(setting("position_error_mm", 1.0)) / 1000.0,
        rotation_error_deg=float(setting("rotation_error_deg", 0.5)))


def export_scene_for(context, library):
    """Export and validate the scene, and write its JSON next to `library`. Returns (path of the
    scene JSON, export warnings). Raises RunSetupError when the scene cannot be sampled."""
    result, invalid = export.export_and_validate(context)
    if result.scene is None or invalid:
        reasons = invalid or result.problems or ["no rigid body world"]
        raise RunSetupError("The scene cannot be sampled: " + "; ".join(reasons), result.problems)
    os.makedirs(os.path.dirname(library) or ".", exist_ok=True)
    scene_json = paths.scene_json_path(library)
    with open(scene_json, "w") as f:
        f.write(result.to_json())
    return scene_json, result.problems


def sample_argv(context, library, first_world, world_count, threads=None, seed=None, duration_s=None):
    """Export the scene and build the engine command that samples worlds
    [first_world, first_world + world_count) of it into `library`, with the scene's run settings
    (threads too, unless given: they change the order worlds are stored in, never the worlds).
    Returns (argv, export warnings); raises RunSetupError or FileNotFoundError (no engine)."""
    engine = paths.engine_path()
    scene_json, warnings = export_scene_for(context, library)
    settings = run_settings(context.scene, seed=seed, duration_s=duration_s)
    if threads is None:
        threads = int(getattr(getattr(context.scene, "mwb", None), "threads", 0))
    argv = engine_process.sample_command(engine, scene_json, library, settings, first_world, world_count, threads)
    return argv, warnings


def library_holds_run(argv):
    """Whether the library of a `sample` command holds that command's run: 'same', 'other', or
    'new' (no library yet). The engine answers from the same arguments it would sample with."""
    result = subprocess.run(list(argv) + ["--dry-run"], capture_output=True, text=True)
    if result.returncode != 0:
        lines = result.stderr.strip().splitlines() or ["the engine failed"]
        raise RunSetupError(lines[0].replace("mwb-engine: ", ""))
    return result.stdout.split()[1]


def _retarget(argv, library):
    """The same sample command writing `library` (its scene JSON beside it)."""
    argv = list(argv)
    old_scene = argv[argv.index("--scene") + 1]
    new_scene = paths.scene_json_path(library)
    if new_scene != old_scene:
        shutil.copyfile(old_scene, new_scene)
    argv[argv.index("--scene") + 1] = new_scene
    argv[argv.index("--out") + 1] = library
    return argv


def sample_into_matching_library(context, library, known, first_world, world_count):
    """The Sample button's run: into `library` if it holds this run (or does not exist yet), else
    into the first of the `known` libraries that does, else into a new library beside it, so a
    changed range, object or setting never stops Sample and never touches the worlds sampled
    before. Returns (argv, library used, export warnings); the first world is ignored for a
    library that is not `library` (its next index is used)."""
    argv, warnings = sample_argv(context, library, first_world, world_count)
    if library_holds_run(argv) in ("same", "new"):
        return argv, library, warnings
    for other in known:
        if other != library and os.path.isfile(other):
            candidate = _retarget(argv, other)
            if library_holds_run(candidate) == "same":
                return _with_first_world(candidate, other, world_count), other, warnings
    new = paths.next_library_path(library, taken=set(known))
    return _with_first_world(_retarget(argv, new), new, world_count), new, warnings


def _with_first_world(argv, library, world_count):
    """The command sampling the next `world_count` worlds after those `library` holds."""
    from . import _native
    first = _native.Library(library, 0.0).next_world_index if os.path.isfile(library) else 0
    argv = list(argv)
    argv[argv.index("--worlds") + 1] = f"{first}:{first + world_count}"
    return argv
