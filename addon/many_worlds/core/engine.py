"""Runs mwb-engine as a child process and follows its progress without blocking the caller.

Bulk sampling never runs ODE inside Blender: a crash or a long run stays in the child. A reader
thread drains stderr (progress lines) and stdout so the child never blocks on a full pipe; the
caller polls `progress()` and `finished()` from a timer.
"""
import signal
import subprocess
import threading
from dataclasses import dataclass

PROGRESS_TAG = "MWB-PROGRESS"


def parse_progress(line):
    """'MWB-PROGRESS 3 10 world 7' -> (3, 10, 7); anything else -> None."""
    parts = line.split()
    if len(parts) >= 3 and parts[0] == PROGRESS_TAG:
        try:
            world = int(parts[4]) if len(parts) >= 5 and parts[3] == "world" else -1
            return int(parts[1]), int(parts[2]), world
        except ValueError:
            return None
    return None


@dataclass(frozen=True)
class RunSettings:
    """What a sampling run is besides the scene and the world range; every setting that changes
    the worlds. Threads are not among them: a world is the same on any thread count."""
    seed: int = 0
    duration_s: float = 0.0          # <= 0: the rigid body world's frame range
    stop_at_rest: bool = True
    alpha: float = 0.1
    position_error_m: float = 0.001
    rotation_error_deg: float = 0.5


def sample_command(engine, scene_json, library, settings, first_world, world_count, threads=0):
    """The argument list of one `mwb-engine sample` run over worlds [first_world, first_world + world_count)
    with the RunSettings `settings`."""
    argv = [engine, "sample", "--scene", scene_json, "--out", library, "--seed", str(int(settings.seed)),
            "--worlds", f"{int(first_world)}:{int(first_world + world_count)}", "--threads", str(int(threads or 0)),
            "--alpha", repr(float(settings.alpha)), "--position-error", repr(float(settings.position_error_m)),
            "--rotation-error", repr(float(settings.rotation_error_deg)), "--progress"]
    if settings.duration_s > 0:
        argv += ["--duration", repr(float(settings.duration_s))]
    if not settings.stop_at_rest:
        argv.append("--no-stop-at-rest")
    return argv


def refine_command(engine, library, world, bodies, time_s, count, threads, first_child=None):
    """The argument list of one `mwb-engine refine` run: `count` children of `world` branching at
    `time_s` (snapped down to a recorded frame by the engine), re-simulating the scene body indices
    `bodies`. The children are appended to `library` itself."""
    argv = [engine, "refine", "--library", library, "--world", str(int(world)),
            "--bodies", ",".join(str(int(b)) for b in bodies), "--time", repr(float(time_s)),
            "--count", str(int(count)), "--threads", str(int(threads)), "--progress"]
    if first_child is not None:
        argv += ["--first-child", str(int(first_child))]
    return argv


def change_bodies_command(engine, library, world, add_names, remove_names, scene_json, count, threads,
                          first_child=None, update_names=()):
    """The argument list of one `mwb-engine refine --add/--remove/--update` run: `count` children of
    `world` in which the objects `add_names` (defined in the scene JSON file `scene_json`) exist from
    0 s, the objects `remove_names` do not, and the objects `update_names` start as `scene_json`
    defines them now (remove + add); what they touch is simulated anew, every other body replays
    the parent. The children are appended to `library` itself.

    Raises ValueError for a call that cannot be expressed: nothing to change, adding or updating
    without a scene, or a name the engine cannot take apart (names are comma-separated on its
    command line).
    """
    add_names, remove_names, update_names = list(add_names), list(remove_names), list(update_names)
    if not add_names and not remove_names and not update_names:
        raise ValueError("nothing to add, remove or update")
    if (add_names or update_names) and not scene_json:
        raise ValueError("adding or updating objects needs the scene JSON that defines them")
    for name in add_names + remove_names + update_names:
        if not name or "," in name:
            raise ValueError(f"the object name {name!r} cannot be passed to the engine: rename it without commas")
    argv = [engine, "refine", "--library", library, "--world", str(int(world))]
    if add_names:
        argv += ["--add", ",".join(add_names), "--scene", scene_json]
    if update_names:
        argv += ["--update", ",".join(update_names)]
        if not add_names:
            argv += ["--scene", scene_json]
    if remove_names:
        argv += ["--remove", ",".join(remove_names)]
    argv += ["--count", str(int(count)), "--threads", str(int(threads)), "--progress"]
    if first_child is not None:
        argv += ["--first-child", str(int(first_child))]
    return argv


class EngineRun:
    """One running `mwb-engine` child. Thread-safe to poll from the UI thread."""

    def __init__(self, argv):
        self.argv = list(argv)
        self._lock = threading.Lock()
        self._done = 0
        self._total = 0
        self._last_world = -1
        self._messages = []
        self._stdout = ""
        self.cancel_requested = False
        self._process = subprocess.Popen(self.argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                         stderr=subprocess.PIPE, text=True, bufsize=1)
        self._reader = threading.Thread(target=self._read, name="mwb-engine-reader", daemon=True)
        self._reader.start()

    def _read(self):
        for line in self._process.stderr:
            progress = parse_progress(line)
            with self._lock:
                if progress:
                    self._done, self._total, self._last_world = progress
                elif line.strip():
                    self._messages.append(line.rstrip("\n"))
        out = self._process.stdout.read()
        with self._lock:
            self._stdout = out

    @property
    def pid(self):
        return self._process.pid

    def progress(self):
        """(worlds finished, worlds to do, index of the last finished world or -1)."""
        with self._lock:
            return self._done, self._total, self._last_world

    def finished(self):
        """True once the child exited and its output was read."""
        return self._process.poll() is not None and not self._reader.is_alive()

    def returncode(self):
        return self._process.poll()

    def messages(self):
        """stderr lines other than progress (errors, repairs)."""
        with self._lock:
            return list(self._messages)

    def summary(self):
        with self._lock:
            return self._stdout.strip()

    def failure(self):
        """None for a clean run or a cancel (which keeps finished worlds); otherwise the first error line."""
        code = self.returncode()
        if code in (None, 0) or (code == 130 and self.cancel_requested):
            return None
        lines = [m for m in self.messages() if m.strip()]
        text = lines[0] if lines else f"mwb-engine exited with code {code}"
        # "mwb-engine: invalid scene:" is a heading; the problem is on the next line.
        if text.endswith(":") and len(lines) > 1:
            text = f"{text} {lines[1].strip()}"
        return text

    def cancel(self):
        """Ask the engine to stop: it finishes writing the current record and exits with 130."""
        if self._process.poll() is None:
            self.cancel_requested = True
            self._process.send_signal(signal.SIGINT)

    def wait(self, timeout=None):
        self._process.wait(timeout)
        self._reader.join(timeout)
        return self._process.returncode

    def kill(self):
        if self._process.poll() is None:
            self._process.kill()
        self.wait(10)
