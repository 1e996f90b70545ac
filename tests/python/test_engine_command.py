"""How the add-on starts the engine: its own executable (mwb-engine.exe on Windows), $MWB_ENGINE, or
the command $MWB_ENGINE_COMMAND gives (a program that runs the engine, such as wine64), held with
the real engine."""
import os
import shlex

import pytest
from conftest import SCENES

from many_worlds.core import engine as engine_process
from many_worlds.core import paths

QUICKSTART = os.path.join(SCENES, "quickstart.json")


def test_the_engine_file_is_named_for_the_platform():
    assert paths.engine_file_name(windows=True) == "mwb-engine.exe"
    assert paths.engine_file_name(windows=False) == "mwb-engine"


def test_without_a_command_the_engine_is_the_one_mwb_engine_names(engine, monkeypatch):
    monkeypatch.delenv("MWB_ENGINE_COMMAND", raising=False)
    monkeypatch.setenv("MWB_ENGINE", engine)
    assert paths.engine_command() == [engine]


def test_a_run_goes_through_the_program_the_command_puts_before_the_engine(native, engine, tmp_path, monkeypatch):
    # env sets the engine's test-only fault for world 2 on the way: a world rejected says it ran.
    monkeypatch.setenv("MWB_ENGINE_COMMAND", f"/usr/bin/env MWB_ENGINE_TEST_FAULTS=2:abort {shlex.quote(engine)}")
    # The command wins over MWB_ENGINE, which names no engine here.
    monkeypatch.setenv("MWB_ENGINE", str(tmp_path / "no-engine"))
    library = tmp_path / "wrapped.mwb"
    sampled = engine_process.run_to_end(engine_process.SampleRequest(
        QUICKSTART, str(library), engine_process.RunSettings(seed=0), 0, 5, threads=2))
    assert sampled.argv[:3] == ["/usr/bin/env", "MWB_ENGINE_TEST_FAULTS=2:abort", engine]
    assert sampled.failure() is None, sampled.log()
    assert sampled.summary()["stored"] == 4 and sampled.summary()["rejected"] == 1
    assert sorted(native.Library(str(library)).world_indices) == [0, 1, 3, 4]
    info = engine_process.run_to_end(engine_process.InfoRequest(str(library)))
    assert info.failure() is None and info.summary()["worlds"] == 4


def test_an_empty_command_is_refused_naming_the_variable(tmp_path, monkeypatch):
    monkeypatch.setenv("MWB_ENGINE_COMMAND", "  ")
    with pytest.raises(FileNotFoundError, match="MWB_ENGINE_COMMAND is set but empty"):
        paths.engine_command()
    with pytest.raises(FileNotFoundError, match="MWB_ENGINE_COMMAND is set but empty"):
        engine_process.EngineProcess(engine_process.InfoRequest(str(tmp_path / "any.mwb")))


def test_a_command_whose_program_is_missing_or_whose_quotes_are_open_is_refused(tmp_path, monkeypatch):
    missing = tmp_path / "wine-not-here"
    monkeypatch.setenv("MWB_ENGINE_COMMAND", f"{missing} mwb-engine.exe")
    with pytest.raises(FileNotFoundError, match=f"MWB_ENGINE_COMMAND: the program '{missing}' is not found"):
        paths.engine_command()
    monkeypatch.setenv("MWB_ENGINE_COMMAND", "wine64 'C:\\engine\\mwb-engine.exe")
    with pytest.raises(FileNotFoundError, match="MWB_ENGINE_COMMAND cannot be split into words: No closing quotation"):
        paths.engine_command()
