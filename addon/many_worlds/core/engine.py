"""Runs mwb-engine as a child process and reads its events without blocking the caller.

Bulk sampling never runs ODE inside Blender: a crash or a long run stays in the child. Every
command is built from a typed request here, and the engine answers in events (JSON lines on its
standard output, common/EngineProtocol.h): nothing here or in a caller reads the engine's text.
A reader thread takes the events as they come and drains stderr, so the child never blocks on
a full pipe; the caller polls `progress()` and `finished()` from a timer.
"""
import json
import subprocess
import threading
from dataclasses import dataclass, field
from typing import Optional, Tuple

from .. import _native
from . import paths

PROTOCOL = _native.engine_protocol
EngineExit = _native.EngineExit
RunSettings = _native.RunSettings
LibraryHolding = _native.LibraryHolding
# The error code of sampling into a library that holds another run (PROTOCOL.ERROR_CODES has it).
OTHER_RUN = "other_run"
# On Windows the engine, a console program, would open a console window of its own beside Blender.
NO_CONSOLE_WINDOW = getattr(subprocess, "CREATE_NO_WINDOW", 0)


# --- requests: one per engine command ---------------------------------------------------------

@dataclass(frozen=True)
class SampleRequest:
    """Sample worlds [first_world, first_world + world_count) of the scene JSON file `scene_json`
    into `library` with `settings` (a RunSettings)."""
    scene_json: str
    library: str
    settings: RunSettings
    first_world: int
    world_count: int
    threads: int = 0

    def arguments(self):
        s = self.settings
        args = ["sample", "--scene", self.scene_json, "--out", self.library, "--seed", str(int(s.seed)),
                "--worlds", f"{int(self.first_world)}:{int(self.first_world + self.world_count)}",
                "--threads", str(int(self.threads or 0)), "--alpha", repr(float(s.alpha)),
                "--position-error", repr(float(s.position_error_m)),
                "--rotation-error", repr(float(s.rotation_error_deg))]
        if s.duration_s > 0:
            args += ["--duration", repr(float(s.duration_s))]
        if not s.stop_at_rest:
            args.append("--no-stop-at-rest")
        return args


@dataclass(frozen=True)
class RefineRequest:
    """`count` children of `world` branching at `time_s` (snapped down to a recorded frame by the
    engine), re-simulating the scene body indices `bodies`; appended to `library` itself."""
    library: str
    world: int
    bodies: Tuple[int, ...]
    time_s: float
    count: int
    threads: int = 0
    first_child: Optional[int] = None

    def arguments(self):
        args = ["refine", "--library", self.library, "--world", str(int(self.world)),
                "--bodies", ",".join(str(int(b)) for b in self.bodies), "--time", repr(float(self.time_s)),
                "--count", str(int(self.count)), "--threads", str(int(self.threads or 0))]
        if self.first_child is not None:
            args += ["--first-child", str(int(self.first_child))]
        return args


@dataclass(frozen=True)
class ChangeRequest:
    """`count` children of `world` in which the objects `add` (defined in the scene JSON file
    `scene_json`) exist from 0 s, the objects `remove` do not, and the objects `update` start as
    `scene_json` defines them now (remove + add); what they touch is simulated anew, every other
    body replays the parent. Appended to `library` itself.

    Raises ValueError for a change that cannot be expressed: nothing to change, adding or updating
    without a scene, or a name the engine cannot take apart (names are comma-separated on its
    command line)."""
    library: str
    world: int
    add: Tuple[str, ...] = ()
    remove: Tuple[str, ...] = ()
    update: Tuple[str, ...] = ()
    scene_json: str = ""
    count: int = 1
    threads: int = 0
    first_child: Optional[int] = None

    def __post_init__(self):
        for name in ("add", "remove", "update"):
            object.__setattr__(self, name, tuple(getattr(self, name)))
        if not self.add and not self.remove and not self.update:
            raise ValueError("nothing to add, remove or update")
        if (self.add or self.update) and not self.scene_json:
            raise ValueError("adding or updating objects needs the scene JSON that defines them")
        for name in self.add + self.remove + self.update:
            if not name or "," in name:
                raise ValueError(f"the object name {name!r} cannot be passed to the engine: rename it without commas")

    def arguments(self):
        args = ["refine", "--library", self.library, "--world", str(int(self.world))]
        if self.add:
            args += ["--add", ",".join(self.add)]
        if self.update:
            args += ["--update", ",".join(self.update)]
        if self.add or self.update:
            args += ["--scene", self.scene_json]
        if self.remove:
            args += ["--remove", ",".join(self.remove)]
        args += ["--count", str(int(self.count)), "--threads", str(int(self.threads or 0))]
        if self.first_child is not None:
            args += ["--first-child", str(int(self.first_child))]
        return args


@dataclass(frozen=True)
class SeekRequest:
    """Refine the worlds of `library` (appending to it) until `want` worlds meet the goal file
    `goal`, within `budget_worlds` new worlds and, when `budget_s` > 0, that many seconds.
    `seed`: the engine's when None."""
    library: str
    goal: str
    want: int
    budget_worlds: int
    budget_s: float = 0.0
    seed: Optional[int] = None
    threads: int = 0

    def arguments(self):
        args = ["seek", "--library", self.library, "--goal", self.goal, "--want", str(int(self.want)),
                "--budget-worlds", str(int(self.budget_worlds)), "--threads", str(int(self.threads or 0))]
        if self.budget_s and self.budget_s > 0:
            args += ["--budget-s", repr(float(self.budget_s))]
        if self.seed is not None:
            args += ["--seed", str(int(self.seed))]
        return args


@dataclass(frozen=True)
class InfoRequest:
    """What the library at `library` holds (the summary's fields are `mwb-engine info --json`'s);
    `as_json`: the summary's text is that JSON, for people who asked for it."""
    library: str
    as_json: bool = False

    def arguments(self):
        return ["info", self.library] + (["--json"] if self.as_json else [])


# --- what runs report --------------------------------------------------------------------------

@dataclass(frozen=True)
class SeekProgress:
    """Where a seek stands after a batch of worlds."""
    boxes_met: int          # by the best world so far
    box_count: int
    worlds_made: int        # by this seek so far
    best_world: int         # -1 while there is none
    worlds_meeting_goal: int
    worlds_rejected: int = 0  # of worlds_made
    text: str = ""            # the engine's line for people: 'best 5 of 6 parts (world 418), ...'


@dataclass(frozen=True)
class SeekOutcome:
    """How a seek ended: the fields of its summary event."""
    reached: bool
    found: Tuple[int, ...]   # worlds meeting every box
    best: int                # the world meeting the most boxes (-1: none)
    best_boxes_met: int
    boxes: int
    worlds_made: int
    seconds: float
    rejected: int = 0        # of worlds_made
    text: str = ""           # the engine's line for people: 'Goal reached: 3 worlds meet ...'

    @classmethod
    def from_summary(cls, fields):
        """The outcome in a seek's summary fields, or None for another command's."""
        if fields is None or "reached" not in fields:
            return None
        return cls(reached=bool(fields["reached"]), found=tuple(int(w) for w in fields["found"]),
                   best=int(fields["best"]), best_boxes_met=int(fields["best_boxes_met"]),
                   boxes=int(fields["boxes"]), worlds_made=int(fields["worlds_made"]),
                   seconds=float(fields["seconds"]), rejected=int(fields.get("rejected", 0)),
                   text=str(fields.get("text", "")))


@dataclass(frozen=True)
class EngineFailure:
    """Why a run failed: the error event's code (one of PROTOCOL.ERROR_CODES; OTHER_PROTOCOL for an
    engine that speaks another protocol version, refused as it starts; "crashed" when the engine
    stopped without saying why) and its message in the user's words."""
    code: str
    message: str
    problems: Tuple[str, ...] = ()


# The code of an EngineFailure for an engine of another protocol version (the add-on's own).
OTHER_PROTOCOL = "other_protocol"


def other_protocol_failure(engine, event):
    """The EngineFailure for a start event of another protocol version than PROTOCOL.VERSION, or
    None when the engine speaks this one."""
    version = event.get("protocol")
    if version == PROTOCOL.VERSION:
        return None
    theirs = f"protocol version {version}" if version is not None else "no protocol version"
    return EngineFailure(OTHER_PROTOCOL, f"the engine {engine} speaks {theirs}, this add-on protocol version "
                                         f"{PROTOCOL.VERSION}: use the engine that came with the add-on")


# --- the running child -------------------------------------------------------------------------

@dataclass
class _RunState:
    done: int = 0
    total: int = 0
    last_world: int = -1
    seek: Optional[SeekProgress] = None
    refused: Optional[EngineFailure] = None  # an engine of another protocol version
    summary: Optional[dict] = None
    error: Optional[EngineFailure] = None
    warnings: list = field(default_factory=list)
    log: list = field(default_factory=list)


class EngineProcess:
    """One running `mwb-engine` child started from a request. Thread-safe to poll from the UI
    thread. `engine`: the executable (when None, paths.engine_command(): the add-on's own, or
    what $MWB_ENGINE_COMMAND says)."""

    def __init__(self, request, engine=None):
        self.request = request
        self.command = [engine] if engine else paths.engine_command()
        self.argv = self.command + request.arguments() + ["--events"]
        self._lock = threading.Lock()
        self._state = _RunState()
        self.cancel_requested = False
        # Binary pipes, decoded per line: an event is UTF-8 whatever the platform's locale.
        self._process = subprocess.Popen(self.argv, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         stderr=subprocess.PIPE, creationflags=NO_CONSOLE_WINDOW)
        self._readers = [threading.Thread(target=self._read_events, name="mwb-engine-events", daemon=True),
                         threading.Thread(target=self._read_log, name="mwb-engine-log", daemon=True)]
        for reader in self._readers:
            reader.start()

    # One reader per event the protocol has; a test holds this table to PROTOCOL.EVENTS.
    def _on_start(self, state, event):
        state.refused = other_protocol_failure(" ".join(self.command), event)
        if state.refused is not None:
            # Its other events may mean other things: none is read, and it stops here.
            self._process.kill()

    def _on_progress(self, state, event):
        state.done, state.total = int(event["done"]), int(event["total"])
        if "seek" in event:
            s = event["seek"]
            state.seek = SeekProgress(int(s["boxes_met"]), int(s["box_count"]), int(s["worlds_made"]),
                                      int(s["best_world"]), int(s["worlds_meeting_goal"]),
                                      int(s.get("worlds_rejected", 0)), str(event.get("text", "")))

    def _on_world(self, state, event):
        state.last_world = int(event["index"])

    def _on_warning(self, state, event):
        state.warnings.append(str(event["message"]))

    def _on_error(self, state, event):
        state.error = EngineFailure(str(event["code"]), str(event["message"]),
                                    tuple(str(p) for p in event.get("problems", ())))

    def _on_summary(self, state, event):
        state.summary = {k: v for k, v in event.items() if k != "event"}

    EVENT_READERS = {"start": _on_start, "progress": _on_progress, "world": _on_world,
                     "warning": _on_warning, "error": _on_error, "summary": _on_summary}

    def _read_events(self):
        for raw in self._process.stdout:
            try:
                event = json.loads(raw.decode("utf-8", "replace"))
                reader = self.EVENT_READERS[event["event"]]
            except (ValueError, KeyError, TypeError):
                # Not an event of this protocol: kept for the log, never interpreted.
                with self._lock:
                    self._state.log.append(raw.decode("utf-8", "replace").rstrip("\n"))
                continue
            with self._lock:
                if self._state.refused is None:
                    reader(self, self._state, event)

    def _read_log(self):
        # Whatever the engine or ODE print for people; shown with a failure, never interpreted.
        for raw in self._process.stderr:
            line = raw.decode("utf-8", "replace").rstrip("\n")
            if line.strip():
                with self._lock:
                    self._state.log.append(line)

    @property
    def pid(self):
        return self._process.pid

    def progress(self):
        """(worlds finished, worlds to do, index of the last finished world or -1)."""
        with self._lock:
            return self._state.done, self._state.total, self._state.last_world

    def seek_progress(self):
        """The last SeekProgress of a seek run, or None before its first batch."""
        with self._lock:
            return self._state.seek

    def finished(self):
        """True once the child exited and its output was read."""
        return self._process.poll() is not None and not any(r.is_alive() for r in self._readers)

    def returncode(self):
        return self._process.poll()

    def warnings(self):
        """The warning events' messages (a repaired library, another engine build)."""
        with self._lock:
            return list(self._state.warnings)

    def log(self):
        """Lines the engine printed besides its events (stderr); for a person, never parsed."""
        with self._lock:
            return list(self._state.log)

    def summary(self):
        """The summary event's fields (its `text` is what a person reads), or None before it."""
        with self._lock:
            return dict(self._state.summary) if self._state.summary is not None else None

    def failure(self):
        """None for a clean run or a cancel (which keeps finished worlds); otherwise an
        EngineFailure (an engine of another protocol version is one, however it exited)."""
        code = self.returncode()
        with self._lock:
            if code is not None and self._state.refused is not None:
                return self._state.refused
        if code is None or code == int(EngineExit.OK) or (code == int(EngineExit.CANCELLED) and self.cancel_requested):
            return None
        with self._lock:
            if self._state.error is not None:
                return self._state.error
            last = self._state.log[-1] if self._state.log else ""
        return EngineFailure("crashed", f"the engine stopped unexpectedly (exit code {code})"
                             + (f": {last}" if last else ""))

    def cancel(self):
        """Ask the engine to stop: it finishes writing the current record and exits with
        EngineExit.CANCELLED. Said on its stdin, as on every OS."""
        if self._process.poll() is None:
            self.cancel_requested = True
            try:
                self._process.stdin.write(b"cancel\n")
                self._process.stdin.flush()
            except (BrokenPipeError, OSError, ValueError):
                pass  # it is ending already

    def wait(self, timeout=None):
        self._process.wait(timeout)
        for reader in self._readers:
            reader.join(timeout)
        self._close_stdin()
        return self._process.returncode

    def _close_stdin(self):
        try:
            self._process.stdin.close()
        except (BrokenPipeError, OSError):
            pass

    def kill(self):
        if self._process.poll() is None:
            self._process.kill()
        self.wait(10)


def run_to_end(request, engine=None):
    """Run a short command (info) to its end. Returns the finished EngineProcess."""
    run = EngineProcess(request, engine)
    run.wait()
    return run
