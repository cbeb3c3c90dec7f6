"""``./softpack run`` end to end with a fake ``softpack-simulate``
(fake_driver.py; the fixtures ``fake_bin`` and ``fake_mesh`` of
conftest.py)."""

import os
from pathlib import Path

import pytest

from fake_driver import SMALL
from softpack import paths
from softpack.analysis import observables
from softpack.simulation import run

pytestmark = pytest.mark.usefixtures("registry")



def test_bad_config_exits_2_and_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[contact]\nfriction = -1\n")
    out = tmp_path / "out"
    assert run.main([str(bad), "--out", str(out)]) == 2
    assert "bad.toml: [contact] friction = -1: must be >= 0" in \
        capsys.readouterr().err
    assert not out.exists()
    assert run.main([str(SMALL), "--friction", "-0.5", "--out",
                     str(out)]) == 2
    assert "(from the command line)" in capsys.readouterr().err
    assert not out.exists()


def test_missing_driver_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(paths, "BIN", tmp_path / "nobin")
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 1
    assert "softpack-simulate not found" in capsys.readouterr().err
    assert not out.exists()


def test_run_with_real_mesh(tmp_path, fake_bin, capsys):
    pytest.importorskip("dolfinx")
    pytest.importorskip("gmsh")
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out), "--seed", "2"]) == 0
    printed = capsys.readouterr().out
    assert "100.0 %" in printed and "ETA" in printed
    for name in ("config.toml", "driver.json", "mesh/packing.xdmf",
                 "mesh/packing.bodies.csv", "mesh/packing.packing.csv",
                 "raw/done.json", "particles.csv", "series.csv"):
        assert (out / name).is_file(), name
    log = (out / "run.log").read_text()
    assert "fake driver: 14 bodies" in log and "[progress]" in log
    assert "seed = 2" in (out / "config.toml").read_text()
    s = observables.read_table(out / "series.csv")
    # meshed polygons (21 edges on a small disk) hold 1.2 % less area
    assert s["phi"][-1] >= 0.80 and 0.68 < s["phi"][0] < 0.6957
    assert set(s["z"]) == {2.0} and set(s["rattlers"]) == {0}
    assert s["eps"][0] == 0 and s["eps"][-1] > 0.1


def test_scene_error_names_the_file_and_the_key(tmp_path, fake_bin,
                                                fake_mesh, capsys):
    """A packing the box cannot give is refused naming the TOML file (not
    "packing:") and the key, before the driver runs."""
    pytest.importorskip("gmsh")  # the disk templates are meshed first
    bad = tmp_path / "too_full.toml"
    bad.write_text(SMALL.read_text().replace(
        "seed = 0", "seed = 0\ninitial_packing_fraction = 0.5"))
    out = tmp_path / "out"
    assert run.main([str(bad), "--out", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"softpack run: {bad}: [packing] initial_packing_fraction = 0.5" \
        in err
    assert "[box] length" in err  # and the key that would make it right
    assert not (out / "driver.json").exists()
    assert not (out / "series.csv").exists()
    assert "scene failed" in (out / "run.log").read_text()


def test_refuses_complete_run_unless_forced(tmp_path, fake_bin, fake_mesh,
                                            capsys):
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    first = (out / "series.csv").read_text()
    assert run.main([str(SMALL), "--out", str(out)]) == 1
    assert "holds a complete run" in capsys.readouterr().err
    assert (out / "series.csv").read_text() == first
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 0


def test_crash_leaves_no_series(tmp_path, fake_bin, fake_mesh, monkeypatch,
                                capsys):
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    monkeypatch.setenv("FAKE_DRIVER", "crash")
    assert run.main([str(SMALL), "--out", str(out), "--force"]) == 1
    err = capsys.readouterr().err
    assert "exit status 3" in err and "NLGS blew up" in err
    assert not (out / "series.csv").exists()
    assert not (out / "particles.csv").exists()
    assert (out / "raw" / "steps.csv").is_file()  # partial raw output kept
    assert run.main(["--observables-only", "--out", str(out)]) == 1
    assert "did not finish" in capsys.readouterr().err


def test_observables_only_uses_the_runs_config(tmp_path, fake_bin,
                                               fake_mesh):
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    config = out / "config.toml"
    config.write_text(config.read_text().replace(
        'two_node_rule = "loaded_nodes"', 'two_node_rule = "candidate_nodes"'))
    (out / "series.csv").unlink()
    assert run.main(["--observables-only", "--out", str(out)]) == 0
    s = observables.read_table(out / "series.csv")
    assert set(s["z"]) == {2.0}  # wall contacts: two nodes of the particle


def test_observables_only_applies_the_observables_settings(
        tmp_path, fake_bin, fake_mesh, capsys):
    """``--set observables.*`` changes the rules (written to the run's
    config.toml first); other settings need a new run and are refused."""
    out = tmp_path / "out"
    assert run.main([str(SMALL), "--out", str(out)]) == 0
    config = (out / "config.toml").read_text()
    assert run.main(["--observables-only", "--out", str(out), "--set",
                     'observables.two_node_rule="candidate_nodes"']) == 0
    s = observables.read_table(out / "series.csv")
    assert set(s["z"]) == {2.0}  # as test_observables_only_uses_the_runs_config
    assert 'two_node_rule = "candidate_nodes"' in (
        out / "config.toml").read_text()
    capsys.readouterr()
    for argv, said in (
            (["--set", "contact.friction=0.1"], "only [observables]"),
            (["--set", "observables.two_node_rule=\"x\""], "two_node_rule"),
            ([str(SMALL)], "no CONFIG")):
        before = (out / "config.toml").read_text()
        assert run.main(["--observables-only", "--out", str(out),
                         *argv]) == 2
        assert said in capsys.readouterr().err
        assert (out / "config.toml").read_text() == before
    assert run.main(["--observables-only"]) == 2
    assert "--out DIR" in capsys.readouterr().err
    assert config != (out / "config.toml").read_text()


def test_progress_counts_a_3d_runs_base_area_fraction(tmp_path):
    """[stop] base_area_fraction: the fraction done is phi_base's way from
    its first row's value to the target (examples/cylinders3d_small.toml:
    0.80), not the time's."""
    from softpack.scene.config import load_config
    config = load_config(paths.ROOT / "examples" / "cylinders3d_small.toml")
    progress = run.Progress(config, tmp_path / "steps.csv")
    rows = [{"step": 0, "time": 0.0, "phi": 0.512, "phi_base": 0.70},
            {"step": 12, "time": 0.001, "phi": 0.52, "phi_base": 0.75}]
    assert " 50.0 %" in progress.line(rows)


def test_default_out_dir_and_progress_line(tmp_path):
    from softpack.scene.config import load_config
    config = load_config(SMALL, {"packing.seed": 4,
                                 "contact.friction": 0.7})
    assert run.default_out_dir(config) == Path("runs/small-seed4")
    assert run.default_out_dir(config, True) == Path("runs/small-seed4-mu0.7")
    line = run.Progress(config, tmp_path / "steps.csv").line(
        [{"step": 10, "time": 0.01, "phi": 0.75}])
    # done = (0.75 - Phi0) / (0.80 - Phi0)
    assert "Phi = 0.7500" in line and " 52.1 %" in line
    # with [stop] steps, the steps done count too
    # (counted from the first row: a run from a state starts past 0)
    progress = run.Progress(load_config(SMALL, {"stop.steps": 40}),
                            tmp_path / "steps.csv")
    line = progress.line([{"step": 100, "time": 0.0, "phi": 0.0},
                          {"step": 130, "time": 0.0, "phi": 0.0}])
    assert " 75.0 %" in line
    assert os.fspath(run._default_config()).endswith("examples/paper.toml")


def test_a_staged_run_shows_its_stage_and_criterion(tmp_path):
    """examples/biaxial_small.toml: an equilibrium stage (its fraction is
    that of its time bound, so its ETA is an upper bound), then a stage
    ended at 10 % strain of the right wall against the left, counted from
    the row where the first stage ended."""
    from softpack.scene.config import load_config
    progress = run.Progress(load_config(paths.ROOT / "examples" /
                                        "biaxial_small.toml"),
                            tmp_path / "steps.csv")

    def row(step, stage, right_x):
        return {"step": step, "time": 1e-4 * step, "stage": stage,
                "phi": 0.7, "left_x": 0.0, "right_x": right_x,
                "bottom_y": 0.0, "top_y": 0.07, "seconds": 1e-3 * step}
    first = [row(0, 0, 0.11), row(300, 0, 0.10)]  # 0.03 of its 0.3 s bound
    line = progress.line(first)
    assert line.startswith("stage 1/2 'consolidate': until equilibrium")
    assert "(10 %)" in line and "stage ETA <= " in line
    rows = first + [row(400, 1, 0.095), row(500, 1, 0.09)]
    line = progress.line(rows)  # (0.10 - 0.09) / 0.10 of 10 %
    assert line.startswith("stage 2/2 'axial': strain 0.1000 of 0.1")
    assert "(100 %)" in line and "<=" not in line
    assert progress.line(rows[:3]).count("strain 0.0500") == 1
    assert progress.mark(rows[:3]) > progress.mark(first)


def test_a_resumed_runs_progress_counts_the_killed_part(tmp_path):
    """A resumed driver's steps.csv starts at the state's step with its
    seconds at zero: the killed part's rows (raw.part) lead them, so the
    stage starts where it did and the pace is the whole run's (the ETA was
    the stage's full length after a resume)."""
    import io
    from softpack.scene.config import load_config
    config = load_config(paths.ROOT / "examples" / "biaxial_small.toml")
    part, steps = tmp_path / "part.csv", tmp_path / "steps.csv"
    header = "step,time,stage,phi,left_x,right_x,bottom_y,top_y,seconds\n"

    def row(step, stage, right_x, seconds):
        return (f"{step},{1e-4 * step},{stage},0.7,0.0,{right_x},0.0,0.07,"
                f"{seconds}\n")
    part.write_text(header + row(0, 0, 0.11, 0) + row(300, 0, 0.10, 300)
                    + row(400, 1, 0.095, 400) + row(500, 1, 0.09, 500))
    # the resumed driver from the state at step 400: seconds from zero
    steps.write_text(header + row(400, 1, 0.095, 0.0)
                     + row(450, 1, 0.0925, 50))
    said = []
    progress = run.Progress(config, steps,
                            lambda text, end="\n": said.append(text), part)
    rows = progress.rows()
    assert [int(r["step"]) for r in rows] == [0, 300, 400, 450]
    assert [r["seconds"] for r in rows] == [0, 300, 400, 450]
    line = progress.line(rows)  # strain (0.10 - 0.0925) / 0.10 of 10 %
    assert line.startswith("stage 2/2 'axial': strain 0.0750 of 0.1")
    # 150 s for the stage's 75 %
    assert "(75 %)" in line and "stage ETA 0m50s" in line
    progress.update(io.StringIO())
    assert said and "(75 %)" in said[-1]


def test_set_overrides_are_parsed_as_toml_values():
    from softpack.scene.config import ConfigError
    from softpack.simulation.run import _parse_settings
    assert _parse_settings(["time.time_step=3.6e-5", "material.law='x'",
                            "output.fields = false",
                            "walls.right.velocity=[-0.2, 0]"]) == {
        "time.time_step": 3.6e-5, "material.law": "x",
        "output.fields": False, "walls.right.velocity": [-0.2, 0]}
    for bad in ("time_step=1", "time.time_step", "material.law=x"):
        with pytest.raises(ConfigError, match="--set"):
            _parse_settings([bad])


def test_the_last_progress_line_is_written_once(tmp_path):
    """A run's final row was logged twice (its 5 % mark, then as final)."""
    import io
    from softpack.scene.config import load_config
    steps = tmp_path / "steps.csv"
    steps.write_text("step,time,phi\n0,0,0.70\n100,0.01,0.80\n")
    said = []
    progress = run.Progress(load_config(SMALL), steps,
                            lambda text, end="\n": said.append(text))
    log = io.StringIO()
    progress.update(log)
    progress.update(log, final=True)
    assert len(said) == 1 and "100.0 %" in said[0]
    assert log.getvalue().count("[progress]") == 1
