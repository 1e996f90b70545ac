"""One engine run the add-on started: sampling, a refinement, a change of objects, a seek.

A Run owns its engine process (core.engine.EngineProcess), says what it does (its kind), where it
writes, how far it got and how it ended; the poller (operators.run_poller) streams its worlds and
turns its progress into the panel's line. Nothing here needs bpy, fork or POSIX signals: a run is
cancelled through the engine protocol.
"""
import enum
from typing import Optional, Tuple

from . import engine as engine_process


class RunKind(enum.Enum):
    """What a run does; the value is the panel's word for it while it runs."""
    SAMPLE = "Sampling"
    REFINE = "Refining"
    ADD = "Adding"
    REMOVE = "Removing"
    UPDATE = "Updating"
    SEEK = "Seeking"


# What a finished run made; {done} is the count of new worlds.
FINISHED_TEXT = {RunKind.SAMPLE: "Sampled {done} worlds", RunKind.REFINE: "Refined into {done} worlds",
                 RunKind.ADD: "Added into {done} new worlds", RunKind.REMOVE: "Removed from {done} new worlds",
                 RunKind.UPDATE: "Updated in {done} new worlds"}


class Run:
    """An engine run started from `request` (core.engine) of scene `scene_name` writing `library`.

    note: why it writes where it does, said again when it ends; world_range: (first, end) of a
    sampling run, remembered if it is cancelled; follower: for a run whose progress is more than
    worlds done, an object whose follow(scene, run) and ended(scene, run, stored) give the panel's
    line. Raises FileNotFoundError when there is no engine.
    """

    def __init__(self, kind, request, scene_name, library, note="", world_range: Optional[Tuple[int, int]] = None,
                 follower=None, engine=None):
        self.kind = kind
        self.request = request
        self.scene_name = scene_name
        self.library = library
        self.note = note
        self.world_range = world_range
        self.follower = follower
        self.ended = False   # set once the poller has read its end
        self.process = engine_process.EngineProcess(request, engine)

    @property
    def label(self):
        return self.kind.value

    @property
    def cancel_requested(self):
        return self.process.cancel_requested

    def progress(self):
        """(worlds finished, worlds to do, index of the last finished world or -1)."""
        return self.process.progress()

    def seek_progress(self):
        return self.process.seek_progress()

    def finished(self):
        return self.process.finished()

    def returncode(self):
        return self.process.returncode()

    def failure(self):
        """None, or the EngineFailure that ended it."""
        return self.process.failure()

    def summary(self):
        return self.process.summary()

    def warnings(self):
        """What the engine warned of (a repaired library, workers it could not start)."""
        return self.process.warnings()

    def cancel(self):
        self.process.cancel()

    def wait(self, timeout=None):
        return self.process.wait(timeout)

    def kill(self):
        self.process.kill()

    def running_text(self, before_progress=""):
        """The panel's line while it runs, for a run without a follower; `before_progress` until
        the engine has said how many worlds it makes."""
        done, total, _ = self.progress()
        return f"{self.label}: {done} / {total} worlds" if total else before_progress

    def finished_text(self, stored):
        """The panel's line once it reached its end; `stored`: worlds the library holds now. It
        counts the worlds the run stored, and says how many it lost and why."""
        summary = self.summary() or {}
        rejected = int(summary.get("rejected", 0))
        kept = int(summary["stored"]) if "stored" in summary else self.progress()[0] - rejected
        made = FINISHED_TEXT.get(self.kind, "{done} new worlds").format(done=kept)
        lost = summary.get("rejected_text", "")
        return f"{made}{'; ' + lost if lost else ''}{self.note}; the library holds {stored}"

    def cancelled_text(self, stored):
        return f"{self.label} cancelled; the library keeps {stored} worlds"
