"""Where the add-on finds the engine and where it writes its files."""
import os
import shlex
import shutil

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The one test of the platform: every difference Windows makes to starting the engine keys on it.
WINDOWS = os.name == "nt"


def engine_file_name(windows=WINDOWS):
    """The engine executable's file name in the package's bin/: 'mwb-engine.exe' on Windows."""
    return "mwb-engine.exe" if windows else "mwb-engine"


def engine_path():
    """The mwb-engine executable: $MWB_ENGINE, else the one the build copies into the package."""
    bundled = os.path.join(PACKAGE_DIR, "bin", engine_file_name())
    path = os.environ.get("MWB_ENGINE") or bundled
    if not os.path.isfile(path):
        raise FileNotFoundError(f"mwb-engine not found at {path}: build the project (cmake --build build) "
                                "or set MWB_ENGINE")
    if not WINDOWS and path == bundled and not os.access(path, os.X_OK):
        # Blender unpacks an installed extension's zip without the files' permission bits.
        os.chmod(path, os.stat(path).st_mode | 0o111)
    return path


def engine_command():
    """The start of the command line that runs the engine, as a list: $MWB_ENGINE_COMMAND split as
    a POSIX shell would (a program that runs the engine, such as 'wine64 /path/mwb-engine.exe';
    a Windows path's backslashes need single quotes), else [engine_path()]. Raises
    FileNotFoundError for an empty or unbalanced $MWB_ENGINE_COMMAND, or one whose program is not
    found (what a caller reports as no engine)."""
    command = os.environ.get("MWB_ENGINE_COMMAND")
    if command is None:
        return [engine_path()]
    try:
        argv = shlex.split(command)
    except ValueError as error:
        raise FileNotFoundError(f"MWB_ENGINE_COMMAND cannot be split into words: {error}")
    if not argv:
        raise FileNotFoundError("MWB_ENGINE_COMMAND is set but empty: give the command that runs mwb-engine "
                                "(or unset it to run the add-on's own engine)")
    if shutil.which(argv[0]) is None:
        raise FileNotFoundError(f"MWB_ENGINE_COMMAND: the program {argv[0]!r} is not found")
    return argv


def default_library_name(blend_path):
    """'shot.blend' -> 'shot.mwb'; an unsaved file has no default."""
    if not blend_path:
        return ""
    return os.path.splitext(os.path.basename(blend_path))[0] + ".mwb"


def next_library_path(library_path, taken=()):
    """A new library beside `library_path` for a changed run: 'shot.mwb' -> 'shot-2.mwb', or the
    first of -3, -4, ... that is neither a file nor in `taken` (absolute paths)."""
    root, ext = os.path.splitext(library_path)
    base = root
    head, dash, number = root.rpartition("-")
    if dash and number.isdigit():
        base = head
    k = 2
    while True:
        candidate = f"{base}-{k}{ext or '.mwb'}"
        if not os.path.exists(candidate) and candidate not in taken:
            return candidate
        k += 1


def scene_json_path(library_path):
    """The exported scene sits next to the library: 'shot.mwb' -> 'shot.scene.json'."""
    root, _ = os.path.splitext(library_path)
    return root + ".scene.json"


def added_scene_json_path(library_path):
    """The scene exported to add bodies to worlds, apart from the sampled one: 'shot.mwb' ->
    'shot.added.scene.json' (each addition rewrites it; the library keeps what it added)."""
    root, _ = os.path.splitext(library_path)
    return root + ".added.scene.json"


def goal_json_path(library_path):
    """The goal of the library's last seek sits next to it: 'shot.mwb' -> 'shot.goal.json'."""
    root, _ = os.path.splitext(library_path)
    return root + ".goal.json"
