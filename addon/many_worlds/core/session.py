"""Runtime state of this Blender session that is not saved: the open library and the engine runs.

What must survive a reload (library path, selected world) lives in scene properties; this holds
only objects that cannot be saved, and is rebuilt from those properties on load.
"""


class Session:
    def __init__(self):
        self.view = None        # LibraryView or None
        self.query = None       # core.library_query.LibraryQuery of `view` (its path index), or None
        self.runs = []          # core.run.Run, oldest first; at most the last one is still running
        self.status = ""        # one line for the panel and status bar
        self.last_error = ""    # engine failure text, shown as a report
        self.run_warnings = []  # what the last run's engine warned of, reported when it ends
        self.box_note = ""      # why the last box drawn was not kept, until the next one is
        self.goal_problem = ""  # which enabled box or pose the module refuses as set, and why
        self.export_warnings = []    # what the last export could not reproduce, one line per object and setting

    @property
    def run(self):
        """The Run under way, or None: one at a time."""
        return self.runs[-1] if self.runs and not self.runs[-1].ended else None

    @property
    def last_kind(self):
        """The RunKind of the newest run, running or ended (whose line the panel shows), or None."""
        return self.runs[-1].kind if self.runs else None

    def close(self):
        if self.run is not None:
            self.run.cancel()
            self.run.wait(30)
        self.runs = []
        if self.query is not None:
            self.query.close()
        self.view = None
        self.query = None
        self.status = ""
        self.goal_problem = ""


SESSION = Session()
