"""The contract between the engine and its callers (common/EngineProtocol.h), held with the real
engine: the events it writes are the ones the add-on reads, the answers that need no process agree
with the engine's own, and failures are told apart by code, never by their words."""
import json
import os
import signal
import subprocess
import sys
import time

import pytest
from conftest import SCENES

from many_worlds.core import engine as engine_process

QUICKSTART = os.path.join(SCENES, "quickstart.json")


def run(engine, request):
    return engine_process.run_to_end(request, engine)


def sample_request(library, first=0, count=4, seed=0, **settings):
    return engine_process.SampleRequest(QUICKSTART, str(library), engine_process.RunSettings(seed=seed, **settings),
                                        first, count, threads=2)


def event_lines(engine, *args):
    result = subprocess.run([engine, *args, "--events"], capture_output=True, text=True)
    return result, [json.loads(line) for line in result.stdout.splitlines()]


def test_every_event_the_engine_can_write_has_a_reader():
    protocol = engine_process.PROTOCOL
    assert set(engine_process.EngineProcess.EVENT_READERS) == set(protocol.EVENTS)
    assert engine_process.OTHER_RUN in protocol.ERROR_CODES
    assert protocol.VERSION >= 1


def fake_engine(folder, protocol):
    """An executable that answers any command as an engine of `protocol` would start to."""
    path = folder / "mwb-engine"
    start = {"event": "start", "protocol": protocol, "command": "info", "engine_build": "fake"}
    summary = {"event": "summary", "text": "a library of 3 worlds"}
    path.write_text(f"#!{sys.executable}\nprint({json.dumps(start)!r}, flush=True)\nprint({json.dumps(summary)!r})\n")
    path.chmod(0o755)
    return str(path)


def test_an_engine_of_another_protocol_version_is_refused_in_one_line(tmp_path):
    ours = engine_process.PROTOCOL.VERSION
    fake = fake_engine(tmp_path, ours + 1)
    refused = run(fake, engine_process.InfoRequest(str(tmp_path / "any.mwb")))
    failure = refused.failure()
    assert failure.code == engine_process.OTHER_PROTOCOL
    assert failure.message == (f"the engine {fake} speaks protocol version {ours + 1}, this add-on protocol "
                               f"version {ours}: use the engine that came with the add-on")
    # Nothing else it said is read.
    assert refused.summary() is None
    accepted = run(fake_engine(tmp_path, ours), engine_process.InfoRequest(str(tmp_path / "any.mwb")))
    assert accepted.failure() is None and accepted.summary()["text"] == "a library of 3 worlds"


def test_every_line_on_stdout_is_an_event_of_the_protocol(engine, tmp_path):
    result, events = event_lines(engine, "sample", "--scene", QUICKSTART, "--out", str(tmp_path / "a.mwb"),
                                 "--worlds", "0:5", "--threads", "2")
    assert result.returncode == 0, result.stderr
    names = [e["event"] for e in events]
    assert names[0] == "start" and names[-1] == "summary" and set(names) <= set(engine_process.PROTOCOL.EVENTS)
    assert events[0]["protocol"] == engine_process.PROTOCOL.VERSION and events[0]["command"] == "sample"
    worlds = [e for e in events if e["event"] == "world"]
    assert sorted(e["index"] for e in worlds) == list(range(5)) and all(e["stored"] for e in worlds)
    assert [e["done"] for e in events if e["event"] == "progress"] == [1, 2, 3, 4, 5]


def test_a_sample_reports_its_worlds_and_parses_the_scene_once(native, engine, tmp_path):
    library = tmp_path / "run.mwb"
    done = run(engine, sample_request(library, count=6))
    assert done.failure() is None and done.returncode() == int(engine_process.EngineExit.OK)
    assert done.progress()[:2] == (6, 6)
    summary = done.summary()
    assert summary["stored"] == 6 and summary["rejected"] == 0 and summary["skipped"] == 0
    assert summary["stored"] == len(native.Library(str(library)).world_indices)
    # The supervisor parses the scene once; each worker parses it once in its own process.
    assert summary["scene_parses"] == 1
    assert summary["text"].startswith("sampled 6 worlds")
    # Again over a range that overlaps: the stored worlds are skipped, not sampled again.
    again = run(engine, sample_request(library, count=8))
    assert again.summary()["skipped"] == 6 and again.summary()["stored"] == 2


def test_the_module_says_which_library_holds_a_run_as_the_engine_decides(native, engine, tmp_path):
    with open(QUICKSTART) as f:
        scene_text = f.read()
    library = tmp_path / "held.mwb"
    settings = engine_process.RunSettings(seed=3, alpha=0.2)
    holding = engine_process.LibraryHolding
    assert native.library_holds_run(str(library), scene_text, settings) == holding.NEW
    assert run(engine, sample_request(library, count=2, seed=3, alpha=0.2)).failure() is None
    assert native.library_holds_run(str(library), scene_text, settings) == holding.SAME
    info = run(engine, engine_process.InfoRequest(str(library))).summary()
    assert info["run_hash"] == native.run_hash(scene_text, settings)
    other = engine_process.RunSettings(seed=3, alpha=0.25)
    assert native.library_holds_run(str(library), scene_text, other) == holding.OTHER
    # A header made once answers as the scene and settings do, for any number of libraries.
    assert native.library_holds_run(str(library), native.run_header(scene_text, settings)) == holding.SAME
    assert native.library_holds_run(str(library), native.run_header(scene_text, other)) == holding.OTHER
    assert native.run_hash(scene_text, other) != info["run_hash"]
    # The engine refuses the run the module called another, by code and exit status.
    refused = run(engine, sample_request(library, count=2, seed=3, alpha=0.25))
    assert refused.returncode() == int(engine_process.EngineExit.BAD_LIBRARY)
    assert refused.failure().code == engine_process.OTHER_RUN
    assert len(native.Library(str(library)).world_indices) == 2


def test_a_damaged_header_is_a_library_error_not_a_crash(native, tmp_path):
    with open(QUICKSTART) as f:
        scene_text = f.read()
    bad = tmp_path / "bad.mwb"
    bad.write_bytes(b"\x89MWB\r\n\x1a\n" + b"\x01\x00\x00\x00" + b"\xff\xff\xff\x7f")
    with pytest.raises(native.LibraryError, match="truncated"):
        native.library_holds_run(str(bad), scene_text, engine_process.RunSettings())
    bad.write_bytes(b"not a library at all")
    with pytest.raises(native.LibraryError, match="not a Many-Worlds library"):
        native.library_holds_run(str(bad), scene_text, engine_process.RunSettings())


def test_failures_carry_a_code_and_the_problems(engine, tmp_path):
    broken = tmp_path / "broken.scene.json"
    broken.write_text('{"format": "many-worlds-scene", "version": 1, "bodies": [{"name": "A"}]}')
    failed = run(engine, engine_process.SampleRequest(str(broken), str(tmp_path / "x.mwb"),
                                                      engine_process.RunSettings(), 0, 2))
    assert failed.returncode() == int(engine_process.EngineExit.INVALID_SCENE)
    failure = failed.failure()
    assert failure.code == "invalid_scene" and failure.problems and failure.message.startswith("invalid scene: ")
    assert not os.path.exists(tmp_path / "x.mwb")
    missing = run(engine, engine_process.InfoRequest(str(tmp_path / "none.mwb")))
    assert missing.failure().code == "bad_library" and "none.mwb" in missing.failure().message


def test_cancel_on_stdin_stops_the_run_and_keeps_its_worlds(native, engine, tmp_path):
    library = tmp_path / "cancelled.mwb"
    started = engine_process.EngineProcess(sample_request(library, count=400), engine)
    while started.progress()[0] < 3 and not started.finished():
        time.sleep(0.01)
    started.cancel()
    assert started.wait(60) == int(engine_process.EngineExit.CANCELLED)
    assert started.failure() is None and started.summary()["cancelled"]
    kept = len(native.Library(str(library)).world_indices)
    assert 3 <= kept < 400 and kept == started.summary()["stored"]


def test_an_engine_that_dies_without_an_error_event_is_reported_as_a_crash(engine, tmp_path):
    library = tmp_path / "killed.mwb"
    started = engine_process.EngineProcess(sample_request(library, count=400), engine)
    while started.progress()[0] < 2 and not started.finished():
        time.sleep(0.01)
    os.kill(started.pid, signal.SIGKILL)
    started.wait(60)
    failure = started.failure()
    assert failure is not None and failure.code == "crashed" and "exit code" in failure.message


def test_each_command_takes_only_its_own_options(engine, tmp_path):
    result, events = event_lines(engine, "sample", "--scene", QUICKSTART, "--out", str(tmp_path / "a.mwb"),
                                 "--goal", "g.json")
    assert result.returncode == int(engine_process.EngineExit.USAGE)
    assert events[-1]["event"] == "error" and events[-1]["code"] == "usage"
    assert events[-1]["message"] == "sample does not take --goal"
    assert not (tmp_path / "a.mwb").exists()
    result, events = event_lines(engine, "info", str(tmp_path / "a.mwb"), "--worlds", "0:3")
    assert events[-1]["message"] == "info does not take --worlds"
    result, events = event_lines(engine, "seek", "--library", "l.mwb", "--goal", "g.json", "--budget-worlds", "3",
                                 "--frobnicate")
    assert events[-1]["message"] == "unknown option --frobnicate"


def test_workers_restarted_mid_run_do_not_hang_a_run_that_listens_for_cancel(native, engine, tmp_path, monkeypatch):
    """The supervisor forks a new worker for each world that crashed one, while the thread that
    listens for "cancel" waits on stdin (left open, as the add-on leaves it): a listener inside
    stdio would hold a lock fork() waits for, and the run would hang at the first crash."""
    monkeypatch.setenv("MWB_ENGINE_TEST_FAULTS", "4:abort,9:segv,15:abort")
    library = tmp_path / "faults.mwb"
    started = engine_process.EngineProcess(sample_request(library, count=24), engine)
    try:
        assert started.wait(120) == int(engine_process.EngineExit.OK)
    finally:
        started.kill()
    summary = started.summary()
    assert summary["rejected"] == 3 and summary["stored"] == 21, summary
    assert sorted(native.Library(str(library)).world_indices) == [w for w in range(24) if w not in (4, 9, 15)]
