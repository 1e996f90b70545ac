"""Where every sampling run starts: the Sample button, the command line and the farm tasks (which
run the command line) export the scene and read the scene's run settings here, and nowhere else,
so the same .blend and world range give the same library whichever way it was started."""
import os

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
    override the scene's when given (the command line's --seed and --duration). A setting the
    scene does not have takes the engine's default."""
    settings = getattr(scene, "mwb", None)
    defaults = engine_process.RunSettings()

    def setting(name, default):
        return getattr(settings, name, default) if settings is not None else default

    return engine_process.RunSettings(
        seed=int(seed if seed is not None else setting("seed", defaults.seed)),
        duration_s=float(duration_s if duration_s is not None else setting("duration_s", defaults.duration_s)),
        stop_at_rest=bool(setting("stop_at_rest", defaults.stop_at_rest)),
        alpha=float(setting("alpha", defaults.alpha)),
        position_error_m=float(setting("position_error_mm", defaults.position_error_m * 1000.0)) / 1000.0,
        rotation_error_deg=float(setting("rotation_error_deg", defaults.rotation_error_deg)))


def export_scene(context):
    """Export and validate the scene. Returns (scene JSON text, export warnings). Raises
    RunSetupError when the scene cannot be sampled."""
    result, invalid = export.export_and_validate(context)
    if result.scene is None or invalid:
        reasons = invalid or result.problems or ["no rigid body world"]
        raise RunSetupError("The scene cannot be sampled: " + "; ".join(reasons), result.problems)
    return result.to_json(), result.problems


def write_scene_json(scene_text, library):
    """Write the exported scene beside `library` (where the engine and later runs find it)."""
    os.makedirs(os.path.dirname(library) or ".", exist_ok=True)
    path = paths.scene_json_path(library)
    with open(path, "w") as f:
        f.write(scene_text)
    return path


def _threads(scene, threads):
    """Engine threads: `threads` when given, else the scene's setting (0: all cores). They change
    the order worlds are stored in, never the worlds."""
    return int(threads if threads is not None else getattr(getattr(scene, "mwb", None), "threads", 0))


def sample_request(context, library, first_world, world_count, threads=None, seed=None, duration_s=None):
    """Export the scene and build the request that samples worlds [first_world, first_world +
    world_count) of it into `library`, with the scene's run settings. Returns (SampleRequest,
    export warnings); raises RunSetupError."""
    scene_text, warnings = export_scene(context)
    settings = run_settings(context.scene, seed=seed, duration_s=duration_s)
    request = engine_process.SampleRequest(write_scene_json(scene_text, library), library, settings,
                                           first_world, world_count, _threads(context.scene, threads))
    return request, warnings


def _run_header(scene_text, settings):
    """The header this scene and settings sample into (the scene parsed once, here)."""
    from . import _native
    try:
        return _native.run_header(scene_text, settings)
    except _native.SceneError as error:
        raise RunSetupError(str(error))


def library_holds_run(library, run):
    """Whether `library` holds the run whose header is `run` (a LibraryHolding), answered by the
    module from the library's header, as the engine itself decides."""
    from . import _native
    try:
        return _native.library_holds_run(library, run)
    except _native.LibraryError as error:
        raise RunSetupError(str(error))


def _next_world_index(library):
    from . import _native
    return _native.Library(library, 0.0).next_world_index if os.path.isfile(library) else 0


def sample_into_matching_library(context, library, known, first_world, world_count):
    """The Sample button's run: into `library` if it holds this run (or does not exist yet), else
    into the first of the `known` libraries that does (after the worlds it holds), else into a new
    library beside it, so a changed range, object or setting never stops Sample and never touches
    the worlds sampled before. Returns (SampleRequest, library used, first world, export warnings)."""
    scene_text, warnings = export_scene(context)
    settings = run_settings(context.scene)
    run = _run_header(scene_text, settings)
    holding = engine_process.LibraryHolding
    if library_holds_run(library, run) in (holding.SAME, holding.NEW):
        target, first = library, first_world
    else:
        target = next((other for other in known if other != library and os.path.isfile(other)
                       and library_holds_run(other, run) == holding.SAME), None)
        first = _next_world_index(target) if target is not None else 0
    if target is None:
        target = paths.next_library_path(library, taken=set(known))
    request = engine_process.SampleRequest(write_scene_json(scene_text, target), target, settings, first,
                                           world_count, _threads(context.scene, None))
    return request, target, first, warnings
