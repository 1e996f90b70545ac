"""Runs mwb-engine as a child process and follows its progress without blocking the caller.

Bulk sampling never runs ODE inside Blender: a crash or a long run stays in the child. A reader
thread drains stderr (progress lines) and stdout so the child never blocks on a full pipe; the
caller polls `progress()` and `finished()` from a timer.
"""
import json
import signal
import subprocess
import threading
from dataclasses import dataclass
from typing import Tuple

PROGRESS_TAG = "MWB-PROGRESS"
SEEK_TAG = "MWB-SEEK"


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
class SeekProgress:
    """Where a seek stands after a batch of worlds."""
    boxes_met: int          # by the best world so far
    box_count: int
    worlds_made: int        # by this seek so far
    best_world: int         # -1 while there is none
    worlds_meeting_goal: int


def parse_seek_progress(line):
    """'MWB-SEEK 5 6 3120 418 0' -> SeekProgress(5, 6, 3120, 418, 0); anything else -> None."""
    parts = line.split()
    if len(parts) < 6 or parts[0] != SEEK_TAG:
        return None
    try:
        return SeekProgress(*(int(v) for v in parts[1:6]))
    except ValueError:
        return None


def _boxes(count):
    return "1 box" if count == 1 else f"{count} boxes"


def seek_progress_text(progress):
    """'best 5 of 6 boxes (world 418), 3,120 worlds made', and how many meet the goal once some do."""
    best = f" (world {progress.best_world})" if progress.best_world >= 0 else ""
    text = (f"best {progress.boxes_met} of {_boxes(progress.box_count)}{best}, "
            f"{progress.worlds_made:,} worlds made")
    if progress.worlds_meeting_goal:
        text += f", {progress.worlds_meeting_goal:,} meet all"
    return text


@dataclass(frozen=True)
class SeekOutcome:
    """How a seek ended: `mwb-engine seek --json` prints it as one JSON object."""
    reached: bool
    found: Tuple[int, ...]   # worlds meeting every box
    best: int                # the world meeting the most boxes (-1: none)
    best_boxes_met: int
    boxes: int
    worlds_made: int
    seconds: float


def parse_seek_outcome(text):
    """The SeekOutcome of `mwb-engine seek --json`'s output, or None when it printed none (a
    cancelled or failed run may end without one)."""
    for line in reversed(text.strip().splitlines()):
        try:
            data = json.loads(line)
        except ValueError:
            continue
        if isinstance(data, dict) and "reached" in data:
            return SeekOutcome(reached=bool(data["reached"]), found=tuple(int(w) for w in data.get("found", [])),
                               best=int(data.get("best", -1)), best_boxes_met=int(data.get("best_boxes_met", 0)),
                               boxes=int(data.get("boxes", 0)), worlds_made=int(data.get("worlds_made", 0)),
                               seconds=float(data.get("seconds", 0.0)))
    return None


def _world_list(worlds, limit=8):
    shown = ", ".join(str(w) for w in worlds[:limit])
    return shown + (f" and {len(worlds) - limit} more" if len(worlds) > limit else "")


def seek_outcome_text(outcome, want):
    """One line on how a seek ended, e.g. 'Goal reached: 3 worlds meet all 6 boxes (412, 415, 430);
    1,204 worlds made in 61.2 s' or 'Budget spent: best world 418 meets 5 of 6 boxes; ...'."""
    made = f"{outcome.worlds_made:,} worlds made in {outcome.seconds:.1f} s"
    found = list(outcome.found)
    noun = "world meets" if len(found) == 1 else "worlds meet"
    every = "the box" if outcome.boxes == 1 else f"all {outcome.boxes} boxes"
    if outcome.reached:
        return f"Goal reached: {len(found)} {noun} {every} ({_world_list(found)}); {made}"
    if found:
        return f"Budget spent: {len(found)} {noun} {every} ({_world_list(found)}) of {want} wanted; {made}"
    if outcome.best < 0:
        return f"Budget spent: no world meets any of the {_boxes(outcome.boxes)}; {made}"
    return (f"Budget spent: best world {outcome.best} meets {outcome.best_boxes_met} of {_boxes(outcome.boxes)}; "
            f"{made}")


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


def seek_command(engine, library, goal, want, budget_worlds, budget_s=0.0, seed=None, threads=0, as_json=False):
    """The argument list of one `mwb-engine seek` run: refine the worlds of `library` (appending to
    it) until `want` worlds meet the goal file `goal`, within `budget_worlds` new worlds and, when
    `budget_s` > 0, that many seconds. `seed`: the engine's when None; `as_json`: the summary as
    one JSON object (SeekOutcome) instead of a line for people."""
    argv = [engine, "seek", "--library", library, "--goal", goal, "--want", str(int(want)),
            "--budget-worlds", str(int(budget_worlds)), "--threads", str(int(threads or 0)), "--progress"]
    if budget_s and budget_s > 0:
        argv += ["--budget-s", repr(float(budget_s))]
    if seed is not None:
        argv += ["--seed", str(int(seed))]
    if as_json:
        argv.append("--json")
    return argv


class EngineRun:
    """One running `mwb-engine` child. Thread-safe to poll from the UI thread."""

    def __init__(self, argv):
        self.argv = list(argv)
        self._lock = threading.Lock()
        self._done = 0
        self._total = 0
        self._last_world = -1
        self._seek = None
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
            seek = parse_seek_progress(line)
            with self._lock:
                if progress:
                    self._done, self._total, self._last_world = progress
                elif seek:
                    self._seek = seek
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

    def seek_progress(self):
        """The last SeekProgress of a seek run, or None before its first batch."""
        with self._lock:
            return self._seek

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
        # Said in the user's words: what went wrong, not which program noticed.
        text = lines[0].replace("mwb-engine: ", "", 1) if lines else f"mwb-engine exited with code {code}"
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
