"""Issue 16 on the Python side: nothing lost, nothing silent.

Each test reproduces one finding of the issue and checks its fix:
item 1 (a foreign ``--out`` kept), item 2 (a killed wrapper takes the
driver with it, and the run never looks complete), item 8 (ordinary
mistakes are one line and exit 2), item 9 (no writes outside the run),
item 11 (an ETA from the cost trend) and item 12 (the Python API).
The driver is the fake one of test_run.py unless a test says otherwise.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from softpack.contract import run_directory
from softpack.simulation import run
from softpack.simulation.progress import remaining_seconds
from fake_driver import FAKE_DRIVER, SMALL

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.usefixtures("registry")


# -- item 1: --out never deletes what softpack did not write ---------------

def test_foreign_directory_is_kept(tmp_path, fake_bin, fake_mesh, capsys):
    out = tmp_path / "D"
    (out / "mesh").mkdir(parents=True)
    (out / "mesh" / "important.msh").write_text("x")
    (out / "notes.txt").write_text("y")
    assert run.main([str(SMALL), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "not a softpack run directory" in err and "--force" in err
    # --force writes next to foreign files, never over them
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 2
    assert "mesh would be overwritten" in capsys.readouterr().err
    assert sorted(p.name for p in out.rglob("*")) == [
        "important.msh", "mesh", "notes.txt"]
    (out / "mesh" / "important.msh").unlink()
    (out / "mesh").rmdir()
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 0
    assert (out / "series.csv").is_file() and (out / run_directory.MARKER).is_file()
    assert (out / "notes.txt").read_text() == "y"


def test_rerun_replaces_only_softpack_outputs(tmp_path, fake_bin,
                                              fake_mesh):
    out = tmp_path / "D"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    (out / "notes.txt").write_text("mine")
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 0
    assert (out / "notes.txt").read_text() == "mine"
    (out / "series.csv").unlink()  # an unfinished run: no --force needed
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    assert (out / "notes.txt").read_text() == "mine"


# -- item 8: ordinary mistakes are one line naming the option, exit 2 ------

def test_bad_out_directories(tmp_path, fake_bin, capsys):
    a_file = tmp_path / "file"
    a_file.write_text("keep")
    assert run.main([str(SMALL), "--out", str(a_file)]) == 2
    assert f"--out {a_file}: is a file" in capsys.readouterr().err
    assert a_file.read_text() == "keep"
    assert run.main([str(SMALL), "--out", "/proc/softpack-x"]) == 2
    assert "--out /proc/softpack-x: cannot write there" in \
        capsys.readouterr().err
    assert run.main([str(SMALL), "--out", str(a_file / "sub")]) == 2
    assert f"--out {a_file / 'sub'}: cannot write there" in \
        capsys.readouterr().err


def test_read_only_directory(tmp_path, fake_bin, monkeypatch, capsys):
    """A read-only directory (as root, chmod is not enough: the write
    itself is refused, as on a read-only mount)."""
    out = tmp_path / "ro"
    out.mkdir()

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Read-only file system")
    monkeypatch.setattr(run_directory.tempfile, "mkstemp", refuse)
    assert run.main([str(SMALL), "--out", str(out)]) == 2
    assert f"--out {out}: cannot write there (Read-only file system)" in \
        capsys.readouterr().err


def test_unknown_set_key_is_blamed_on_the_command_line(tmp_path, capsys):
    for setting, blame in (("contact.frictio=0.2", "--set contact.frictio"),
                           ("nosection.x=1", "--set nosection.x"),
                           ("species.0.cont=1", "--set species.0.cont")):
        assert run.main([str(SMALL), "--out", str(tmp_path / "o"),
                         "--set", setting]) == 2
        err = capsys.readouterr().err.strip()
        assert err.startswith(f"softpack run: {blame}: unknown"), err
        assert "small.toml" not in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("args, message", [
    (["--time-step", "0"], "argument --time-step: must be > 0, not 0"),
    (["--element-size", "-1"],
     "argument --element-size: must be > 0, not -1"),
    (["--every", "x"], "argument --every: 'x' is not an integer"),
])
def test_single_disk_bad_options(tmp_path, args, message):
    result = _softpack_cli(["single-disk", "--out", str(tmp_path / "o"),
                            *args])
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.strip().splitlines()[-1] == \
        f"softpack single-disk: error: {message}"
    assert not (tmp_path / "o").exists()


def test_single_disk_out_is_a_file(tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("keep")
    result = _softpack_cli(["single-disk", "--out", str(a_file),
                            "--max-strain", "0.01"])
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert f"--out {a_file}: is a file, not a directory" in result.stderr


def _softpack_cli(argv, **kwargs):
    """``python -m softpack.cli ARGV`` with this checkout's package."""
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    return subprocess.run([sys.executable, "-m", "softpack.cli", *argv],
                          capture_output=True, text=True, env=env,
                          timeout=120, **kwargs)


# -- item 2: the driver dies with the wrapper; no run looks complete -------

@pytest.fixture
def slow_run(tmp_path, registry):
    """A ``softpack run`` child process on a slow fake driver (60 s).

    Yields a function starting it (stdout: a pipe) and returning the
    process once the driver has written its pid; the run directory is
    ``tmp_path / "run"``.
    """
    pytest.importorskip("gmsh")
    pytest.importorskip("dolfinx")
    bin_dir = tmp_path / "build" / "bin"
    bin_dir.mkdir(parents=True)
    exe = bin_dir / "softpack-simulate"
    exe.write_text(FAKE_DRIVER)
    exe.chmod(0o755)
    (tmp_path / "build" / "forms").mkdir()
    (tmp_path / "build" / "forms" / "materials.json").write_text(
        Path(registry).read_text())
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"),
               SOFTPACK_BIN=str(bin_dir), FAKE_DRIVER="slow")
    out = tmp_path / "run"
    started = []

    def start():
        proc = subprocess.Popen(
            [sys.executable, "-m", "softpack.cli", "run", str(SMALL),
             "--out", str(out)], env=env, stdout=subprocess.PIPE,
            stderr=subprocess.PIPE, text=True)
        started.append(proc)
        deadline = time.time() + 60
        while not (out / "driver.pid").is_file():
            assert proc.poll() is None, proc.stderr.read()
            assert time.time() < deadline, "the driver never started"
            time.sleep(0.05)
        time.sleep(0.3)  # the pid written, rows on their way
        return proc, int((out / "driver.pid").read_text())

    yield start
    for proc in started:
        if proc.poll() is None:
            proc.kill()
        proc.wait()


def _gone(pid, within=3.0) -> bool:
    """Whether process ``pid`` is gone (or a zombie) within some seconds."""
    deadline = time.time() + within
    while time.time() < deadline:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().split(") ")[1][0]
        except (FileNotFoundError, ProcessLookupError):
            return True
        if state in "ZX":
            return True
        time.sleep(0.05)
    return False


def _looks_incomplete(out: Path) -> bool:
    return not (out / "series.csv").exists() and \
        not (out / "raw" / "done.json").exists()


@pytest.mark.skipif(not sys.platform.startswith("linux"),
                    reason="parent-death signal: Linux")
def test_sigkill_of_the_wrapper_kills_the_driver(slow_run, tmp_path):
    proc, pid = slow_run()
    os.kill(proc.pid, signal.SIGKILL)
    assert _gone(pid), "softpack-simulate outlived its wrapper"
    assert _looks_incomplete(tmp_path / "run")


def test_sigterm_stops_the_driver_and_says_so(slow_run, tmp_path):
    proc, pid = slow_run()
    os.kill(proc.pid, signal.SIGTERM)
    assert proc.wait(timeout=15) == 128 + signal.SIGTERM
    assert _gone(pid)
    assert "stopped (SIGTERM)" in proc.stderr.read()
    out = tmp_path / "run"
    assert _looks_incomplete(out)
    assert "stopped (SIGTERM)" in (out / "run.log").read_text()


def test_closed_output_stops_the_driver(slow_run, tmp_path):
    """``./softpack run ... | head -3``: the reader goes away."""
    proc, pid = slow_run()
    proc.stdout.close()  # the next progress line meets a closed pipe
    assert proc.wait(timeout=30) == 128 + signal.SIGPIPE
    assert _gone(pid)
    assert "Traceback" not in proc.stderr.read()
    assert _looks_incomplete(tmp_path / "run")


# -- item 9: no writes outside the run -------------------------------------

def test_mesher_writes_nothing_in_home(tmp_path):
    """gmsh (through FLTK) rewrote ~/.fltk/fltk.org/fltk.prefs (and, as
    root, /etc/fltk/...) on every initialisation."""
    pytest.importorskip("gmsh")
    home = tmp_path / "home"
    home.mkdir()
    system = Path("/etc/fltk/fltk.org/fltk.prefs")
    before = system.stat().st_mtime_ns if system.exists() else None
    code = ("from softpack.scene.mesh import disk_triangulation;"
            "m = disk_triangulation([0.01], 3e-3);"
            "print(len(m[0.01][1]))")
    env = dict(os.environ, HOME=str(home), PYTHONPATH=str(ROOT / "python"))
    result = subprocess.run([sys.executable, "-c", code], env=env,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert int(result.stdout) > 20  # a real mesh was made
    assert list(home.rglob("*")) == []
    after = system.stat().st_mtime_ns if system.exists() else None
    assert after == before


def test_plot_of_several_runs_writes_nothing_in_the_cwd(tmp_path,
                                                        monkeypatch):
    pytest.importorskip("matplotlib")
    from test_plots import fake_run
    from softpack.plots import paper

    runs = [fake_run(tmp_path / f"mu0.3-seed{s}", 0.3, s) for s in (0, 1)]
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    monkeypatch.chdir(cwd)
    assert paper.main([str(r) for r in runs]) == 0
    assert list(cwd.iterdir()) == []
    assert (runs[0] / "figures" / "fig4_phi_eps.png").is_file()


# -- item 11: an honest ETA --------------------------------------------------

def test_eta_follows_a_growing_cost():
    """Cost per unit progress c(f) = c0 (1 + k f): spent(f) = c0 (f +
    k f^2 / 2), so at f the rest takes c0 [(1 + k/2) - (f + k f^2/2)]."""
    c0, k = 10.0, 3.0
    f = np.linspace(0.0, 0.25, 26)
    spent = c0 * (f + k * f ** 2 / 2)
    truth = c0 * ((1 + k / 2) - spent[-1] / c0)
    naive = spent[-1] * (1 - f[-1]) / f[-1]
    assert naive < 0.5 * truth  # the old estimate: half the true rest
    assert remaining_seconds(f, spent) == pytest.approx(truth, rel=1e-3)
    # a constant cost stays constant; a finished run has nothing left
    assert remaining_seconds(f, c0 * f) == pytest.approx(c0 * 0.75,
                                                          rel=1e-6)
    assert remaining_seconds([0, 0.5, 1.0], [0, 1, 2]) == 0.0
    assert np.isnan(remaining_seconds([0.0], [0.0]))
    # a busy machine: 20 % noise on each interval's cost, still within 5 %
    rng = np.random.default_rng(16)
    f = np.linspace(0.0, 0.25, 101)
    cost = c0 * (1 + k * 0.5 * (f[1:] + f[:-1]))
    noisy = np.concatenate(([0.0], np.cumsum(
        np.diff(f) * cost * rng.uniform(0.8, 1.2, len(cost)))))
    assert remaining_seconds(f, noisy) == pytest.approx(truth, rel=0.05)
    # a falling cost is not extrapolated below the recent pace
    spent = c0 * (f - f ** 2)
    late_pace = (spent[-1] - spent[50]) / (f[-1] - f[50])
    assert remaining_seconds(f, spent) == pytest.approx(late_pace * 0.75)
    # few rows: the pace so far; stalled rows (no progress) are ignored
    assert remaining_seconds([0, 0.1, 0.1, 0.2], [0, 1, 1.5, 2]) == \
        pytest.approx(8.0)


def test_progress_line_uses_the_drivers_seconds(tmp_path):
    from softpack.scene.config import load_config
    from softpack.simulation.progress import Progress

    progress = Progress(load_config(SMALL, {"stop.steps": 100}),
                        tmp_path / "steps.csv")
    rows = [{"step": s, "time": 0.0, "phi": 0.0,
             "seconds": 0.01 * s + 0.0001 * s * s} for s in range(0, 30, 2)]
    line = progress.line(rows)
    # cost per step 0.01 + 2e-4 step (s): the rest 0.01 * 72 + 1e-4 *
    # (100^2 - 28^2) = 1.64 s
    assert " 28.0 %" in line and "ETA 0m02s" in line


# -- item 12: the Python API ----------------------------------------------

def test_python_api_runs_and_reads(tmp_path, fake_bin, fake_mesh, capsys):
    import softpack

    config = softpack.load_config(SMALL, {"contact.friction": 0.1})
    series = softpack.run(config, tmp_path / "mu0.1")
    assert capsys.readouterr().out == ""  # quiet unless verbose=True
    phi = np.asarray(series["phi"])
    assert phi[-1] >= 0.80 and np.all(np.diff(phi) > 0)
    particles = softpack.read_run(tmp_path / "mu0.1", "particles")
    assert len(np.asarray(particles["particle"])) == 14 * len(phi)
    setup = json.loads((tmp_path / "mu0.1" / "raw" / "setup.json")
                       .read_text())
    assert setup["parameters"]["contact"]["friction"] == 0.1
    with pytest.raises(softpack.RunError, match="complete run"):
        softpack.run(SMALL, tmp_path / "mu0.1")
    with pytest.raises(FileNotFoundError, match="finished run"):
        softpack.read_run(tmp_path)


def test_import_softpack_is_light_and_reference3d_is_a_command():
    code = ("import sys, softpack; from softpack import cli;"
            "assert callable(softpack.run) and callable(softpack.plot_runs);"
            "print(sorted(m.split('.')[0] for m in sys.modules"
            " if m.split('.')[0] in ('dolfinx', 'gmsh', 'matplotlib')));"
            "print(cli.COMMANDS['reference3d'])")
    result = subprocess.run([sys.executable, "-c", code], cwd="/",
                            env=dict(os.environ,
                                     PYTHONPATH=str(ROOT / "python")),
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split("\n")[:2] == [
        "[]", "softpack.references.cylinder3d"]
    help_text = _softpack_cli(["reference3d", "--help"])
    assert help_text.returncode == 0
    assert "usage: softpack reference3d" in help_text.stdout


# -- item 3: a killed run resumed gives the uninterrupted series -----------

@pytest.mark.parametrize("api", [False, True])
def test_resume_gives_the_uninterrupted_series(tmp_path, fake_bin,
                                               fake_mesh, monkeypatch,
                                               capsys, api):
    from softpack.contract.tables import read_table

    whole, part = tmp_path / "whole", tmp_path / "part"
    assert run.main([str(SMALL), "--out", str(whole)]) == 0
    monkeypatch.setenv("FAKE_DRIVER", "crash")  # dies after 3 outputs
    assert run.main([str(SMALL), "--out", str(part)]) == 1
    assert not (part / "series.csv").exists()
    # the resumed run is killed too (at once): resumed again below
    assert run.main(["--resume", str(part)]) == 1
    assert (part / "raw.part").is_dir()
    monkeypatch.setenv("FAKE_DRIVER", "ok")
    capsys.readouterr()
    if api:  # softpack.resume: the same, from Python
        import softpack
        assert len(softpack.resume(part)["phi"]) > 3
        assert "from its state at step 30" in \
            (part / "run.log").read_text()
    else:
        assert run.main(["--resume", str(part)]) == 0
        assert "from its state at step 30" in capsys.readouterr().out
    for name in ("series.csv", "particles.csv", "raw/steps.csv",
                 "raw/particles.csv"):
        a, b = read_table(whole / name), read_table(part / name)
        assert a.keys() == b.keys(), name
        for column in a:
            if column != "seconds":
                np.testing.assert_array_equal(a[column], b[column],
                                              err_msg=f"{name}: {column}")
    s = read_table(part / "series.csv")
    assert np.all(s["piston_force"] != 0)  # the state's row is the old one
    assert np.all(np.diff(read_table(part / "raw/steps.csv")["seconds"]) >= 0)
    assert sorted(p.name for p in (whole / "raw" / "contacts").iterdir()) \
        == sorted(p.name for p in (part / "raw" / "contacts").iterdir())
    assert not (part / "raw.part").exists()
    assert not (part / "resume-state.bin").exists()
    # nothing left to resume
    assert run.main(["--resume", str(part)]) == 1
    assert "nothing to resume" in capsys.readouterr().err
    assert run.main(["--resume", str(tmp_path)]) == 2


def test_a_killed_run_copied_elsewhere_resumes_into_the_copy(
        tmp_path, fake_bin, fake_mesh, monkeypatch):
    """driver.json holds absolute paths: a copied run directory's resumed
    driver wrote into the original one (truncating the original's raw
    output while its own driver went on)."""
    import json
    import shutil

    original, copy = tmp_path / "original", tmp_path / "copy"
    monkeypatch.setenv("FAKE_DRIVER", "crash")
    assert run.main([str(SMALL), "--out", str(original)]) == 1
    shutil.copytree(original, copy)
    before = {p.relative_to(original): p.read_bytes()
              for p in original.rglob("*") if p.is_file()}
    monkeypatch.setenv("FAKE_DRIVER", "ok")
    assert run.main(["--resume", str(copy)]) == 0
    assert (copy / "series.csv").is_file()
    after = {p.relative_to(original): p.read_bytes()
             for p in original.rglob("*") if p.is_file()}
    assert after == before
    doc = json.loads((copy / "driver.json").read_text())
    assert doc["directory"] == str(copy.resolve())
    assert str(original) not in json.dumps(doc)


def test_resume_with_the_real_driver_is_bit_for_bit(tmp_path):
    """The real driver from a state: the series of an uninterrupted run,
    every column but the wall-clock seconds, at the default settings
    (modified Newton: the iteration matrix kept for up to
    time.tangent_reuse_steps steps). The state carries the kept matrix
    (its age, the last step's iteration count and the displacement it was
    assembled at), so the resumed run takes the same refactor decisions
    and does the same arithmetic. The run goes past step 50, where the
    matrix of step 1 reaches the reuse limit after the resume."""
    pytest.importorskip("dolfinx")
    from softpack.contract.tables import read_table
    from softpack.scene.config import load_config
    from driver_required import require_driver
    require_driver()
    sets = {"stop.steps": 70, "output.fields": False}
    whole, part = tmp_path / "whole", tmp_path / "part"
    assert run.run(load_config(SMALL, sets), whole, verbose=False) == 0
    # a run killed after its output at step 30: stopped there, then its
    # complete-run files removed (what a kill leaves: raw/ up to step 30)
    assert run.run(load_config(SMALL, {**sets, "stop.steps": 30}), part,
                   verbose=False) == 0
    for name in ("series.csv", "particles.csv", "raw/done.json"):
        (part / name).unlink()
    toml = part / "config.toml"
    toml.write_text(toml.read_text().replace("steps = 30", "steps = 70"))
    assert run.main(["--resume", str(part)]) == 0
    a, b = read_table(whole / "series.csv"), read_table(part / "series.csv")
    assert len(a["step"]) == 8 and a.keys() == b.keys()
    assert not load_config(SMALL, sets)["time"]["full_newton"]
    for column in a:
        if column != "seconds":
            np.testing.assert_array_equal(a[column], b[column],
                                          err_msg=column)


def test_a_non_finite_newton_iterate_stops_the_run_before_its_step(tmp_path):
    """examples/mixture_small.toml with its old packing (seed 0) and the
    right wall pushed at 200 kPa (a servo wall starting at rest hits the
    packing at ~6 m/s): an element inverts at step 45 and the velocity
    becomes NaN. The run must stop there, naming the step, and write no
    row or state past the last finite step (std::max passed over the NaN
    and the step was taken, written and resumed from, before the check)."""
    from driver_required import require_driver
    from softpack.contract.tables import read_table
    require_driver()
    text = (ROOT / "examples" / "mixture_small.toml").read_text()
    text = text.replace("seed = 8", "seed = 0").replace(
        "velocity = [-0.5, 0.0]", 'control = "pressure"\npressure = 2.0e5')
    assert "seed = 0" in text and "pressure = 2.0e5" in text
    config = tmp_path / "jam.toml"
    config.write_text(text)
    out = tmp_path / "run"
    p = _softpack_cli(["run", str(config), "--out", str(out),
                       "--set", "output.every_steps=1",
                       "--set", "output.fields=false"])
    assert p.returncode == 1
    log = (out / "run.log").read_text()
    assert "a Newton iterate of the velocity is not finite" in log
    steps = read_table(out / "raw" / "steps.csv")
    assert np.all(np.isfinite(steps["phi"]))
    assert np.all(np.isfinite(steps["kinetic_energy"]))
    assert f"step {int(steps['step'][-1]) + 1} " in log
    assert not (out / "raw" / "done.json").exists()
