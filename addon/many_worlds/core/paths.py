"""Where the add-on finds the engine and where it writes its files."""
import os

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def engine_path():
    """The mwb-engine executable: $MWB_ENGINE, else the one the build copies into the package."""
    bundled = os.path.join(PACKAGE_DIR, "bin", "mwb-engine")
    path = os.environ.get("MWB_ENGINE") or bundled
    if not os.path.isfile(path):
        raise FileNotFoundError(f"mwb-engine not found at {path}: build the project (cmake --build build) "
                                "or set MWB_ENGINE")
    if path == bundled and not os.access(path, os.X_OK):
        # Blender unpacks an installed extension's zip without the files' permission bits.
        os.chmod(path, os.stat(path).st_mode | 0o111)
    return path


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
