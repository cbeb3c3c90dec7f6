"""Issue 42, the last edge cases: a run that finishes flagged says so in its
exit status and through the API (item 2); a user's folder holding files of
a run's names is not taken for a run (item 1); the API refuses what is not
a configuration before writing anything (item 6); a missing or broken shape
file is one line and exit 2 (item 5); a bad state file is refused before
anything is written or moved, and the API's messages name its arguments
(item 9, part).

A run whose contact solves stop unconverged (``contact.nlgs_max_sweeps =
2``) used to warn, mark raw/done.json ``converged: false`` and exit 0, and
``softpack.run()`` returned normally: a script could not tell.
"""

import warnings
from pathlib import Path

import numpy as np
import pytest

import softpack
from driver_required import require_driver
from softpack.contract.run_directory import (EXIT_DONE, EXIT_FAILED,
                                             EXIT_FLAGGED, EXIT_USAGE,
                                             RunDirectory, RunError,
                                             RunFlagged, RunLock, run_flags)
from softpack.scene.config import load_config
from softpack.simulation import run

from fake_driver import SMALL

pytestmark = pytest.mark.usefixtures("registry")

#: A short run (60 steps of examples/small.toml: the disks touch from step
#: ~2 on) whose contact solves stop after two sweeps, unconverged.
UNCONVERGED = {"contact.nlgs_max_sweeps": 2, "stop.steps": 60,
               "output.fields": False}


def _cli_settings():
    return [a for key, value in UNCONVERGED.items()
            for a in ("--set", f"{key}={str(value).lower()}")]


def test_the_flags_of_a_finished_run():
    assert run_flags({"converged": True, "overlap_steps": 0}) == []
    assert run_flags({}) == []  # an older done.json marks nothing
    flags = run_flags({"converged": False, "newton_unconverged_steps": 0,
                       "nlgs_unconverged_steps": 4, "overlap_steps": 2,
                       "complete": False, "stage": 1, "reason": "max_time"})
    assert [f.split(" (")[0] for f in flags] == [
        "incomplete", "not converged", "overlapping"]
    assert "4 contact solve steps" in flags[1]


def test_an_unconverged_run_exits_3(tmp_path, capsys):
    require_driver()
    out = tmp_path / "X"
    status = run.main([str(SMALL), "--out", str(out), *_cli_settings()])
    assert status == EXIT_FLAGGED == 3
    err = capsys.readouterr().out
    assert "finished flagged (exit status 3): not converged" in err
    # every output is written all the same
    assert (out / "series.csv").is_file() and (out / "particles.csv").is_file()


def test_the_api_raises_on_a_flagged_run_unless_told_not_to(tmp_path):
    require_driver()
    config = load_config(SMALL, UNCONVERGED)
    with pytest.raises(RunFlagged) as caught:
        softpack.run(config, tmp_path / "strict")
    assert isinstance(caught.value, RunError)
    assert [f.split(" (")[0] for f in caught.value.flags] == ["not converged"]
    assert len(caught.value.series["step"]) > 1
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        series = softpack.run(config, tmp_path / "lenient", strict=False)
    assert len(series["step"]) == len(caught.value.series["step"])
    assert any(issubclass(w.category, RuntimeWarning)
               and "not converged" in str(w.message) for w in seen)


def test_a_converged_run_is_not_flagged(tmp_path):
    require_driver()
    config = load_config(SMALL, {"stop.steps": 60, "output.fields": False})
    assert run.run(config, tmp_path / "ok", verbose=False) == EXIT_DONE


# -- item 1: only a folder softpack marked is taken for a run --------------

def test_a_users_folder_with_run_file_names_is_kept(tmp_path, fake_bin,
                                                    fake_mesh, capsys):
    out = tmp_path / "D"
    (out / "mesh").mkdir(parents=True)
    (out / "config.toml").write_text("x")
    (out / "driver.json").write_text("{}")
    (out / "mesh" / "important.msh").write_text("m")
    status = run.main([str(SMALL), "--out", str(out), "--set",
                       "stop.steps=20"])
    assert status == 2
    assert "not a softpack run directory" in capsys.readouterr().err
    assert (out / "config.toml").read_text() == "x"
    assert (out / "driver.json").read_text() == "{}"
    assert (out / "mesh" / "important.msh").read_text() == "m"
    assert sorted(p.name for p in out.rglob("*")) == [
        "config.toml", "driver.json", "important.msh", "mesh"]
    # nor resumed
    assert run.main(["--resume", str(out)]) == 2


# -- item 6: softpack.run given something else than a configuration -------

def test_the_api_refuses_a_plain_dict_before_writing(tmp_path):
    out = tmp_path / "OUT"
    with pytest.raises(TypeError, match="config is a dict"):
        softpack.run({"contact": {"friction": 0.1}}, out)
    assert not out.exists()


# -- item 5: a missing or broken .geo file: one line, exit 2, nothing written

@pytest.mark.parametrize("content", [
    None,                                           # no such file
    "Point(1) = {0, 0, 0};\nLine(1) = {1, 2};\n",   # a gmsh syntax error
    "Point(1) = {0, 0, 0};\nPoint(2) = {1, 0, 0};\n",  # no surface
], ids=["missing", "syntax-error", "no-surface"])
def test_a_bad_geo_file_is_refused_before_anything_is_written(
        content, tmp_path, fake_bin, capsys):
    pytest.importorskip("gmsh")
    geo = tmp_path / "shape.geo"
    if content is not None:
        geo.write_text(content)
    out = tmp_path / "G"
    status = run.main([str(SMALL), "--out", str(out),
                       "--set", 'species.0.shape="geo"',
                       "--set", f'species.0.file="{geo}"'])
    captured = capsys.readouterr()
    assert status == 2
    lines = [line for line in (captured.out + captured.err).splitlines()
             if line.strip()]
    assert len(lines) == 1, lines
    assert "[species.0]" in lines[0] and "shape.geo" in lines[0]
    assert not out.exists()


# -- item 9: a bad state is refused before anything is written or moved ---

def test_a_missing_or_corrupt_from_state_is_a_usage_error(tmp_path, capsys):
    require_driver()
    out = tmp_path / "F"
    missing = tmp_path / "none.bin"
    assert run.main([str(SMALL), "--out", str(out), "--from-state",
                     str(missing)]) == EXIT_USAGE
    bad = tmp_path / "bad.bin"
    bad.write_bytes(b"not a state file")
    assert run.main([str(SMALL), "--out", str(out), "--from-state",
                     str(bad)]) == EXIT_USAGE
    err = capsys.readouterr().err
    assert f"--from-state: {missing}: no such file" in err
    assert "--from-state:" in err and "bad.bin" in err
    assert not out.exists()  # no packing, mesh or driver started


def test_a_corrupt_state_is_refused_before_resume_moves_anything(tmp_path,
                                                                 capsys):
    require_driver()
    out = tmp_path / "R"
    assert run.main([str(SMALL), "--out", str(out), "--set", "stop.steps=20",
                     "--set", "output.fields=false"]) == EXIT_DONE
    directory = RunDirectory(out)
    # as a killed run leaves it, but for its state file
    directory.series_csv.unlink()
    directory.raw.done_json.unlink()
    directory.raw.state_bin.write_bytes(b"not a state file")
    capsys.readouterr()
    assert run.main(["--resume", str(out)]) == EXIT_FAILED
    err = capsys.readouterr().err
    assert "raw/state.bin" in err
    assert directory.raw.path.is_dir() and not directory.raw_part.path.exists()


# -- item 7: one run or resume at a time in a directory ---------------------

def test_a_second_run_or_resume_on_a_working_directory_is_refused(
        tmp_path, capsys):
    import os
    import signal
    import subprocess
    import sys
    import time

    require_driver()
    out = tmp_path / "W"
    env = dict(os.environ, PYTHONPATH=str(Path(softpack.__file__).parents[1]))
    first = subprocess.Popen(
        [sys.executable, "-m", "softpack.cli", "run", str(SMALL),
         "--out", str(out), "--set", "stop.max_time=100",
         "--set", "output.fields=false"],
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        steps = RunDirectory(out).raw.steps_csv
        deadline = time.time() + 120
        while not (steps.is_file() and steps.stat().st_size > 2000):
            assert first.poll() is None, first.stderr.read().decode()
            assert time.time() < deadline, "the first run never stepped"
            time.sleep(0.2)
        capsys.readouterr()
        assert run.main(["--resume", str(out)]) == EXIT_USAGE
        assert run.main([str(SMALL), "--out", str(out), "--force"]) \
            == EXIT_USAGE
        err = capsys.readouterr().err
        assert f"process {first.pid}" in err and "working in it" in err
        assert first.poll() is None  # the first run went on, untouched
    finally:
        first.send_signal(signal.SIGTERM)
        first.wait(timeout=60)
    # its lock went with it: the directory is free again
    with RunLock(out):
        pass


# -- items 3 and 4: a run resumed twice reads as one time series -----------

def _start(*args):
    import os
    import subprocess
    import sys

    env = dict(os.environ, PYTHONPATH=str(Path(softpack.__file__).parents[1]))
    return subprocess.Popen([sys.executable, "-m", "softpack.cli", "run",
                             *args], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)


def _stop_after(proc, steps_csv, rows):
    """SIGTERM once steps.csv has more than `rows` rows; its row count."""
    import signal
    import time

    deadline = time.time() + 180
    while True:
        n = (len(steps_csv.read_text().splitlines()) - 1
             if steps_csv.is_file() else 0)
        if n > rows or proc.poll() is not None:
            break
        assert time.time() < deadline, "the run never got there"
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=60)
    return n


def test_a_run_killed_and_resumed_twice_reads_as_one_time_series(tmp_path):
    meshio = pytest.importorskip("meshio")
    require_driver()
    out = tmp_path / "R"
    settings = ["--set", "walls.right.velocity=[-0.05, 0]",
                "--set", "stop.max_time=0.1",
                "--set", "output.every_steps=5"]
    steps = RunDirectory(out).raw.steps_csv
    first = _stop_after(_start(str(SMALL), "--out", str(out), *settings),
                        steps, 8)
    assert not RunDirectory(out).series_csv.exists()
    _stop_after(_start("--resume", str(out)), steps, 8)
    assert run.main(["--resume", str(out)]) == EXIT_DONE
    series = softpack.read_run(out)
    with meshio.xdmf.TimeSeriesReader(out / "fields.xdmf") as reader:
        reader.read_points_cells()
        times = []
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            assert point_data["displacement"].shape[1] == 3
            times.append(t)
    # every output of every segment has its frame, once, in time order
    assert times == sorted(set(times))
    assert np.allclose(times, np.asarray(series["time"]), rtol=0,
                       atol=1e-12), (first, times)


# -- item 9: the API's messages name its arguments, not command-line flags --

def test_api_messages_name_the_api_arguments(tmp_path):
    require_driver()
    config = load_config(SMALL, {"output.fields": False})
    with pytest.raises(RunError) as caught:
        softpack.run(config, tmp_path / "A", initial_state=tmp_path / "no.bin")
    assert "initial_state" in str(caught.value)
    assert "--from-state" not in str(caught.value)
    with pytest.raises(RunError) as caught:
        softpack.run(config, tmp_path / "B", ranks=1000)
    assert "ranks 1000" in str(caught.value) and "--" not in str(caught.value)
    out = tmp_path / "C"  # a run directory with no state to resume from
    out.mkdir()
    (out / ".softpack-run").write_text("x")
    (out / "config.toml").write_text(SMALL.read_text())
    with pytest.raises(RunError) as caught:  # nothing to resume from
        softpack.resume(out)
    assert "--resume" not in str(caught.value)
    assert str(caught.value).startswith("directory ")
