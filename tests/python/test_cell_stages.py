"""A periodic cell's drive in [[stages]] and its mean-stress control
(docs/periodic_cell.md, "Stages in a cell" and "Mean stress"; issue 38 item
2).

Validation: a stage's cell drive that cannot hold (a stress-controlled
component with an imposed rate, the mean stress with a component under
stress, a stress on an imposed component, a negative stress, a stage
cell table without a cell, a stage criterion measured on walls, a stage
without its time bound) is refused before anything runs, naming the key.
End to end, examples/compress_shear_small.toml shortened (compacted by a
mean stress for 0.03 s, then sheared at constant sigma_yy for 0.02 s): the
stage column switches, the shear starts at the stage change (and
stress.csv's gamma with it), the balance
closes with the cell's work, and the run cut inside either stage and
continued from its state gives the uninterrupted run's raw/steps.csv to the
bit (every column but the seconds).
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from softpack.contract.run_directory import EXIT_FLAGGED
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.scene.config import ConfigError, validate
from softpack.simulation.run import run

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" \
    / "compress_shear_small.toml"
CELL = {"enabled": True, "a1": [0.1, 0.0], "a2": [0.0, 0.1]}
BASE = {"box": {"enabled": False}, "cell": CELL,
        "damping": {"alpha": 0.0},
        "stop": {"packing_fraction": 0.0},
        "contact": {"alert_distance": 1e-3, "max_penetration": 1.5e-3},
        "time": {"time_step": 1e-4},
        "species": [{"diameter": 0.02, "count": 10}],
        "mesh": {"element_size": 3e-3}}
COMPACT = {"cell": {"control_mean": "stress", "stress_mean": 2e3},
           "stop": {"max_time": 0.05}}

pytestmark = pytest.mark.usefixtures("registry")


def staged(*stages, **sections):
    return {**BASE, **sections, "stages": list(stages)}


@pytest.mark.parametrize("data, keys", [
    (staged(COMPACT, {"cell": {"velocity_gradient_y": [0.0, -1.0],
                               "control_yy": "stress", "stress_yy": 1e3},
                      "stop": {"max_time": 0.05}}),
     ["[stages.1] cell.control_yy = \"stress\"",
      "[stages.1] cell.velocity_gradient_y[1]"]),
    (staged({"cell": {"control_mean": "stress", "stress_mean": 1e3,
                      "control_xx": "stress", "stress_xx": 1e3},
             "stop": {"max_time": 0.05}}),
     ["[stages.0] cell.control_mean = \"stress\"",
      "[stages.0] cell.control_xx = \"stress\""]),
    (staged({"cell": {"stress_mean": 1e3}, "stop": {"max_time": 0.05}}),
     ["[stages.0] cell.stress_mean = 1000.0", "control_mean"]),
    (staged({"cell": {"control_mean": "stress", "stress_mean": -2e3},
             "stop": {"max_time": 0.05}}),
     ["stress_mean", "-2000.0"]),
    (staged({"cell": {"velocity_gradient_x": [0.0, 2.0],
                      "control_xy": "stress", "stress_xy": 500.0},
             "stop": {"max_time": 0.05}}),
     ["[stages.0] cell.control_xy = \"stress\"",
      "[stages.0] cell.velocity_gradient_x[1]"]),
    (staged({"cell": {"stress_xy": -500.0}, "stop": {"max_time": 0.05}}),
     ["[stages.0] cell.stress_xy = -500.0", "control_xy"]),
    (staged({"cell": {"control_mean": "stress", "stress_mean": 1e3,
                      "control_xy": "stress", "stress_xy": 100.0},
             "stop": {"max_time": 0.05}}),
     ["[stages.0] cell.control_mean = \"stress\"",
      "[stages.0] cell.control_xy = \"stress\""]),
    (staged({"cell": {"stress_rate": 1e4}, "stop": {"max_time": 0.05}}),
     ["[stages.0] cell.stress_rate = 10000.0",
      "without a stress-controlled component"]),
    (staged({"cell": {"control_yy": "stres"}, "stop": {"max_time": 0.05}}),
     ["control_yy", "stres"]),
    (staged({"cell": {"stress": 1e3}, "stop": {"max_time": 0.05}}),
     ["[stages.0.cell] stress"]),
    (staged({"cell": {"control_mean": "stress", "stress_mean": 1e3}}),
     ["[stages.0] stop.max_time missing"]),
    (staged({**COMPACT, "stop": {"pressure": 1e3, "max_time": 0.05}}),
     ["[stages.0] stop.pressure"]),
    ({**staged(COMPACT), "cell": {**CELL, "enabled": False}},
     ["[stages.0] cell", "[cell] enabled = false"]),
    ({**BASE, "cell": {**CELL, "stress_mean": 1e3},
      "stop": {"packing_fraction": 0.0, "max_time": 0.05}},
     ["[cell] stress_mean = 1000.0", "control_mean"]),
    ({**BASE, "cell": {**CELL, "control_mean": "stress",
                       "control_yy": "stress", "stress_yy": 1e3},
      "stop": {"packing_fraction": 0.0, "max_time": 0.05}},
     ["[cell] control_mean = \"stress\"", "[cell] control_yy"]),
])
def test_bad_cell_drives_are_refused_naming_the_keys(data, keys):
    with pytest.raises(ConfigError) as err:
        validate(data, "x.toml")
    for key in keys:
        assert key in str(err.value)


def test_the_example_resolves_and_reloads():
    config = cfg.load_config(EXAMPLE)
    compact, shear = config["stages"]
    assert compact["cell"]["control_mean"] == "stress"
    assert shear["cell"]["control_mean"] == "velocity"
    assert shear["cell"]["velocity_gradient_x"] == [0.0, 2.0]
    assert config["stop"]["max_time"] == pytest.approx(0.35)
    again = validate(tomllib.loads(cfg.to_toml(config)), "again")
    assert again["stages"] == config["stages"]


def short_example():
    """The example with stages of 0.03 and 0.02 s (500 steps)."""
    data = tomllib.loads(EXAMPLE.read_text())
    data["stages"][0]["stop"]["max_time"] = 0.03
    data["stages"][1]["stop"]["max_time"] = 0.02
    data["output"]["every_steps"] = 10
    return data


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    require_driver()
    out = tmp_path_factory.mktemp("cell_stages") / "whole"
    assert run(validate(short_example(), "whole"), out) == 0
    return out


def test_the_shear_starts_at_the_stage_change(whole):
    steps = read_table(whole / "raw" / "steps.csv")
    stage = np.asarray(steps["stage"])
    assert set(stage) == {0, 1}
    a2x = np.asarray(steps["cell_a2x"])
    a1x = np.asarray(steps["cell_a1x"])
    compact = stage == 0
    # the isotropic mode keeps the cell rectangular, then a2 leans at the
    # constant L_xy h_yy (h_yy at the stage's start, its row the compaction's
    # last: about 0.16 m/s, 3.2 mm over 0.02 s) with a1 fixed
    assert np.all(a2x[compact] == 0.0)
    start = np.asarray(steps["cell_a2y"])[compact][-1]
    assert a2x[-1] == pytest.approx(2.0 * 0.02 * start, rel=1e-9)
    assert np.all(a1x[~compact] == a1x[compact][-1])
    # compacted by the mean stress from Phi0 0.695
    assert steps["phi"][-1] > steps["phi"][0] + 0.05


def test_gamma_is_the_shear_from_the_shear_stages_start(whole):
    """stress.csv's gamma: 0 through the compaction, then L_xy (t - t_s)
    with t_s the shear stage's start (the driver's dh/dt = L h0, h0 the
    cell at the stage's start), not the shear over the initial height."""
    steps = read_table(whole / "raw" / "steps.csv")
    st = read_table(whole / "stress.csv")
    stage = np.asarray(steps["stage"])
    t = np.asarray(st["time"])
    t_s = t[stage == 0][-1]
    assert np.all(np.asarray(st["gamma"])[stage == 0] == 0.0)
    assert np.asarray(st["gamma"])[stage == 1] == pytest.approx(
        2.0 * (t[stage == 1] - t_s), rel=1e-9, abs=1e-12)


def test_the_balance_closes_with_the_cells_work(whole):
    steps = read_table(whole / "raw" / "steps.csv")
    work = np.asarray(steps["cell_work"])
    residual = np.abs(np.asarray(steps["energy_residual"]))
    assert work[-1] > 0
    # measured at most 7.4e-5 of the final cell work (1.77 J/m; 2026-12-03)
    assert np.max(residual) < 3e-4 * work[-1], np.max(residual) / work[-1]


def _same_rows(whole_dir, rest_dir, after):
    """raw/steps.csv of the continued run = the uninterrupted one's rows
    after the cut, every column but the seconds, to the bit."""
    a = read_table(whole_dir / "raw" / "steps.csv")
    b = read_table(rest_dir / "raw" / "steps.csv")
    keep = np.asarray(a["step"]) > after
    later = np.asarray(b["step"]) > after
    assert keep.sum() == later.sum() > 0
    for key in a:
        if not key.startswith("seconds"):
            assert np.array_equal(np.asarray(a[key])[keep],
                                  np.asarray(b[key])[later]), key


@pytest.mark.parametrize("stage", [0, 1])
def test_a_run_cut_inside_a_stage_and_continued_is_the_same(whole, stage,
                                                            tmp_path):
    """Cut inside the compaction (the mean-stress mode's V is state, and the
    drive changes after the continuation) or inside the shear (the stage's
    drive set before the state's rates)."""
    steps = read_table(whole / "raw" / "steps.csv")
    inside = np.flatnonzero(np.asarray(steps["stage"]) == stage)
    cut_at = int(steps["step"][inside[len(inside) // 2]])
    data = short_example()
    data["stop"]["steps"] = cut_at
    first = tmp_path / "first"
    assert run(validate(data, "cut"), first) == EXIT_FLAGGED
    data["stop"]["steps"] = 0
    rest = tmp_path / "rest"
    assert run(validate(data, "rest"), rest,
               initial_state=first / "raw" / "state.bin") == 0
    _same_rows(whole, rest, cut_at)
