"""The add-on's Blender-free helpers (many_worlds.core), in plain Python: array shaping for baking,
engine requests, paths, lineage."""
from types import SimpleNamespace

import numpy as np

from many_worlds.core import arrays, engine, export_warnings, family, library_query, paths


def test_bake_frames_cover_the_world_and_map_to_recorded_frames():
    # 121 frames at 120 Hz = 1 s = 24 frames after frame 10 at 24 fps.
    frames = arrays.bake_scene_frames(10, 24.0, 120.0, 121)
    assert frames[0] == 10 and frames[-1] == 34
    assert np.allclose(arrays.world_frame_of_scene_frame(frames, 10, 24.0, 120.0), 5 * np.arange(25))
    # 25 fps does not divide 120 Hz: fractional recorded frames, interpolated.
    assert np.allclose(arrays.world_frame_of_scene_frame([11], 10, 25.0, 120.0), [4.8])


def test_a_sample_request_passes_every_run_setting():
    settings = engine.RunSettings(seed=5, duration_s=3.0, stop_at_rest=False, alpha=0.25)
    argv = engine.SampleRequest("s.json", "l.mwb", settings, 10, 4, 2).arguments()
    assert argv[0] == "sample" and argv[argv.index("--scene") + 1] == "s.json"
    assert argv[argv.index("--worlds") + 1] == "10:14" and argv[argv.index("--seed") + 1] == "5"
    assert "--no-stop-at-rest" in argv and argv[argv.index("--duration") + 1] == "3.0"
    assert argv[argv.index("--alpha") + 1] == "0.25"
    # Settings left unset are the engine's own defaults, read from the one definition.
    default = engine.RunSettings()
    assert (default.alpha, default.position_error_m, default.rotation_error_deg) == (0.1, 0.001, 0.5)
    assert paths.scene_json_path("/a/shot.mwb") == "/a/shot.scene.json"
    assert paths.default_library_name("/x/shot.blend") == "shot.mwb"


def test_a_change_request_adds_and_removes_by_name():
    argv = engine.ChangeRequest("l.mwb", 3, add=["Ball", "Cup"], scene_json="l.added.scene.json", count=8,
                                threads=2).arguments()
    assert argv[:5] == ["refine", "--library", "l.mwb", "--world", "3"]
    assert argv[argv.index("--add") + 1] == "Ball,Cup" and argv[argv.index("--scene") + 1] == "l.added.scene.json"
    assert "--remove" not in argv and "--time" not in argv and "--bodies" not in argv
    assert argv[argv.index("--count") + 1] == "8"
    argv = engine.ChangeRequest("l.mwb", 3, add=["Box.001"], remove=["Box"], scene_json="s.json", count=4,
                                first_child=100).arguments()
    assert argv[argv.index("--remove") + 1] == "Box" and argv[argv.index("--first-child") + 1] == "100"
    argv = engine.ChangeRequest("l.mwb", 3, remove=["Box"], count=4).arguments()
    assert "--add" not in argv and "--scene" not in argv
    for add, remove, scene, phrase in (([], [], "s.json", "nothing to add, remove or update"),
                                       (["Ball"], [], "", "needs the scene JSON"),
                                       (["a,b"], [], "s.json", "without commas")):
        try:
            engine.ChangeRequest("l.mwb", 3, add=add, remove=remove, scene_json=scene, count=4)
        except ValueError as error:
            assert phrase in str(error)
        else:
            raise AssertionError(f"no error for {add} {remove} {scene!r}")
    assert paths.added_scene_json_path("/a/shot.mwb") == "/a/shot.added.scene.json"


def test_lineage_steps_name_the_bodies_added_and_removed():
    class Library:
        def __init__(self, infos):
            self.infos = infos

        def world_info(self, world):
            return self.infos[world]

    def step(time_s, world, bodies, added=(), removed=()):
        return SimpleNamespace(branch_time_s=time_s, world=world, bodies=bodies, added=added, removed=removed)

    def info(parent, time_s, lineage):
        return SimpleNamespace(parent_world=parent, branch_time_s=time_s, root_world=0, lineage=lineage)

    sampled = info(-1, 0.0, [])
    refined = info(0, 1.5, [step(1.5, 1, [2])])
    changed = info(1, 0.0, [step(1.5, 1, [2]), step(0.0, 2, [], [3], [0, 2])])
    library = Library({0: sampled, 1: refined, 2: changed})
    lines = {w: family.lineage_of(library, w) for w in (0, 1, 2)}
    assert (lines[0].added, lines[0].removed) == ((), ())
    assert (lines[1].added, lines[1].removed) == ((), ())
    assert (lines[2].added, lines[2].removed) == ((3,), (0, 2))
    names = ["Box", "Cup", "Plate", "Ball"]
    assert family.relation_text(lines[0], names) == "sampled"
    assert family.relation_text(lines[1], names) == "child of 0 at 1.50 s"
    assert family.relation_text(lines[2], names) == "child of 1: +Ball -Box -Plate"
    assert family.relation_text(lines[2]) == "child of 1: +3 -0 -2"
    assert family.family(lines, 1) == {0: family.ROOT, 1: family.SELECTED, 2: family.CHILD}


def test_the_panel_folds_one_approximation_on_many_objects_into_a_line_naming_them_all():
    joints = [f"Joint{k}: spring_damping_ang: angular spring damping is approximated" for k in range(4)]
    lines = ["Box: scale: negative scale is mirrored", *joints,
             "Shelf: breaking_threshold: breaking is approximated", "Lid: breaking_threshold: breaking is approximated"]
    grouped = export_warnings.grouped_warning_lines(lines)
    assert grouped == ["Box: scale: negative scale is mirrored",
                       "spring_damping_ang on 4 objects (Joint0, Joint1, Joint2, Joint3): angular spring damping "
                       "is approximated",
                       "Shelf: breaking_threshold: breaking is approximated",
                       "Lid: breaking_threshold: breaking is approximated"]
    # Every object is still named; a line that is not "object: setting: reason" stays as it is.
    assert export_warnings.grouped_warning_lines(["odd line"]) == ["odd line"]


def test_the_viewport_label_names_the_world_its_rest_time_and_the_goal_parts_it_meets():
    assert library_query.world_label_text(216, 5.4701) == "World 216 \u00b7 5.47 s"
    assert library_query.world_label_text(216, 5.4701, 3, 3) == "World 216 \u00b7 5.47 s \u00b7 3 of 3 parts"
    assert library_query.world_label_text(7, 0.5, 0, 1) == "World 7 \u00b7 0.50 s \u00b7 0 of 1 part"


def test_a_hundred_constraints_with_one_approximation_fold_into_one_line_that_counts_them():
    # A Cell Fracture wall joined with Connect: one line per constraint and one per piece.
    constraints = [f"Constraint.{k:03d}" if k else "Constraint" for k in range(118)]
    pieces = [f"Wall_cell.{k:03d}" if k else "Wall_cell" for k in range(36)]
    lines = [f"{c}: breaking_threshold: breaking is approximated" for c in constraints]
    lines += [f"{p}: collision_margin: the margin is left out" for p in pieces]
    grouped = export_warnings.grouped_warning_lines(lines, constraints=set(constraints))
    assert grouped == [
        "breaking_threshold on 118 constraints (Constraint, Constraint.001, Constraint.002, … and 115 more): "
        "breaking is approximated",
        "collision_margin on 36 objects (Wall_cell, Wall_cell.001, Wall_cell.002, … and 33 more): "
        "the margin is left out"]


class _Log:
    """A log file's stream (not a terminal) that keeps what was written."""
    def __init__(self, tty=False):
        self.text, self.tty = "", tty

    def isatty(self):
        return self.tty

    def write(self, text):
        self.text += text

    def flush(self):
        pass


def test_a_long_run_writes_one_progress_line_per_interval_to_a_log_and_its_last_state():
    from many_worlds.core.progress_printer import ProgressPrinter
    now = [0.0]
    log = _Log()
    printer = ProgressPrinter(log, interval_s=5.0, clock=lambda: now[0])
    # 5,000 worlds over 100 s of run: one progress message every 20 ms.
    for k in range(1, 5001):
        now[0] = k * 0.02
        printer.update(f"sampled {k}/5000 worlds")
    printer.finish()
    lines = log.text.splitlines()
    assert len(lines) <= 100 / 5 + 2, len(lines)
    assert lines[0] == "sampled 1/5000 worlds" and lines[-1] == "sampled 5000/5000 worlds"


def test_on_a_terminal_progress_rewrites_one_line_and_ends_it_before_other_output():
    from many_worlds.core.progress_printer import ProgressPrinter
    tty = _Log(tty=True)
    printer = ProgressPrinter(tty)
    for k in (1, 2, 10):
        printer.update(f"sampled {k}/10 worlds")
    printer.interrupt()
    tty.write("a warning\n")
    printer.finish()
    assert tty.text.count("\n") == 2 and tty.text.count("\r") == 3
    assert tty.text.split("\n")[0].split("\r")[-1].rstrip() == "sampled 10/10 worlds"


def test_a_rankings_values_get_the_decimals_that_tell_neighbours_apart():
    from many_worlds.core.library_query import decimals_telling_apart
    assert decimals_telling_apart([9.97, 10.93, 11.47, 11.47]) == 2, "equal values stay equal"
    assert decimals_telling_apart([11.466, 11.474, 47.03]) == 3
    assert decimals_telling_apart([1.23441, 1.23449]) == 4
    assert decimals_telling_apart([1.234441, 1.234449]) == 2, "no more than four: alike at four, alike at two"
    assert decimals_telling_apart([]) == 2
