"""Runtime state of this Blender session that is not saved: the open library and the engine run.

What must survive a reload (library path, selected world) lives in scene properties; this holds
only objects that cannot be saved, and is rebuilt from those properties on load.
"""


class Session:
    def __init__(self):
        self.view = None        # LibraryView or None
        self.query = None       # core.library_query.LibraryQuery of `view` (its path index), or None
        self.engine = None      # EngineRun or None
        self.status = ""        # one line for the panel and status bar
        self.last_error = ""    # engine failure text, shown as a report
        self.sampling_scene = ""    # name of the scene being sampled
        self.sampling_library = ""  # absolute path the engine writes
        self.run_label = "Sampling"  # what the engine run does: Sampling, Refining, Adding, Removing, Seeking
        self.sampling_range = None   # (first, end) worlds of the sampling run under way
        self.run_note = ""           # why the run writes where it does, when that is news to the user
        self.run_follower = None     # what turns the run's progress into the panel's line (operators.sampling.start_run)
        self.export_warnings = []    # what the last export could not reproduce, one line per object and setting

    def close(self):
        if self.engine is not None:
            self.engine.cancel()
            self.engine.wait(30)
            self.engine = None
        self.run_follower = None
        if self.query is not None:
            self.query.close()
        self.view = None
        self.query = None
        self.status = ""


SESSION = Session()
