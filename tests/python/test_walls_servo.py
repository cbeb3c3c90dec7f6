"""Servo walls from the TOML file to the driver (issue 12).

Validation: a wall driven two ways, a pressure on a wall with no length, an
unknown control and out-of-range values are refused naming the key; the
walls' mass is derived from the particles. End to end on the 14-disk case
(examples/isotropic_small.toml: right and top walls at 4 kPa, left and
bottom fixed): once the assembly is at rest each servo wall holds its
pressure, the boundary and Love-Weber stresses agree, and the energy
balance closes with the work of the imposed pressure at every output row;
tolerances ~10x the values measured on this run (2026-12-03, given with
each test).
"""

import os
import tomllib
from pathlib import Path

import numpy as np
import pytest

from softpack.analysis.stress import write_stress
from softpack.contract.run_directory import RunDirectory
from softpack.contract.tables import read_table
from softpack.scene import config as cfg
from softpack.scene.species import total_area
from softpack.simulation.run import run
from driver_required import require_driver

ROOT = Path(os.environ.get("SOFTPACK_ROOT",
                           Path(__file__).resolve().parents[2]))
TARGET = 4000.0  # examples/isotropic_small.toml's pressure (Pa)


@pytest.mark.parametrize("walls, key", [
    ({"right": {"control": "pressure", "pressure": 1e3,
                "velocity": [-0.1, 0]}}, r"\[walls.right\] velocity"),
    ({"right": {"velocity": [-0.1, 0], "pressure": 1e3}},
     r"\[walls.right\] pressure"),
    ({"top": {"control": "force", "force": 5.0, "pressure": 1e3}},
     r"\[walls.top\] pressure"),
    ({"lid": {"point": [0, 0.1], "normal": [0, -1], "control": "pressure",
              "pressure": 1e3}}, r"\[walls.lid\] control"),
    ({"right": {"control": "stress"}}, r"walls.right.*control"),
    ({"right": {"control": "pressure", "pressure": -5.0}},
     r"walls.right.*pressure"),
    ({"right": {"control": "pressure", "pressure": 1e3, "mass": 0.0}},
     r"walls.right.*mass"),
])
def test_bad_wall_controls_are_refused_naming_the_key(walls, key):
    with pytest.raises(cfg.ConfigError, match=key):
        cfg.validate({"walls": walls, "stop": {"max_time": 0.1}}, "a.toml")


def test_the_walls_mass_is_the_particles_mass():
    c = cfg.validate({"walls": {"right": {"control": "pressure",
                                          "pressure": 1e3}},
                      "stop": {"max_time": 0.1}}, "a.toml")
    expected = c["material"]["density"] * total_area(c["species"])
    assert c["walls"]["right"]["mass"] == pytest.approx(expected)
    assert c["walls"]["right"]["control"] == "pressure"
    # the resolved TOML (box walls with their control) reloads to the same
    # walls
    again = cfg.validate(tomllib.loads(cfg.to_toml(c)), "b.toml")
    assert again["walls"] == c["walls"]


def test_the_walls_mass_counts_each_species_density():
    """Two species of equal size, one of a material four times denser: the
    servo wall's mass is 1 x + 4 x their area, not [material]'s density
    times all of it."""
    c = cfg.validate({
        "walls": {"top": {"control": "force", "force": 10.0}},
        "stop": {"max_time": 0.1},
        "material": {"density": 1000.0},
        "materials": {"heavy": {"density": 4000.0}},
        "species": [{"name": "light", "diameter": 0.02, "count": 10},
                    {"name": "dense", "diameter": 0.02, "count": 10,
                     "material": "heavy"}]}, "a.toml")
    half = 10 * np.pi * 0.02**2 / 4  # each species' area (m^2)
    assert c["walls"]["top"]["mass"] == pytest.approx(5000.0 * half)
    assert c["walls"]["top"]["mass"] != pytest.approx(2000.0 * half)
    # a mass the file gives is kept
    c = cfg.validate({"walls": {"top": {"control": "force", "force": 1.0,
                                        "mass": 0.5}},
                      "stop": {"max_time": 0.1}}, "a.toml")
    assert c["walls"]["top"]["mass"] == 0.5


@pytest.fixture(scope="module")
def servo_run(tmp_path_factory):
    require_driver()
    out = tmp_path_factory.mktemp("servo") / "run"
    config = cfg.load_config(ROOT / "examples" / "isotropic_small.toml")
    assert run(config, out) == 0
    write_stress(out)
    raw = RunDirectory(out).raw
    return read_table(raw.steps_csv), read_table(RunDirectory(out).stress_csv)


def test_the_servo_walls_hold_their_pressure_at_rest(servo_run):
    steps, stress = servo_run
    # At rest: the kinetic energy a ten-thousandth of the work done
    # (measured 9.2e-6).
    assert steps["kinetic_energy"][-1] < 1e-4 * steps["wall_work"][-1]
    # measured 2026-12-03: 8.5e-4 (right), 8.6e-4 (top) below the target
    for wall in ("right", "top"):
        assert stress[f"{wall}_stress"][-1] == pytest.approx(TARGET,
                                                             rel=8e-3)
    # both moved in: the box shrank in both directions
    assert stress["eps_xx"][-1] > 0.01 and stress["eps_yy"][-1] > 0.01


def test_wall_and_contact_stresses_agree_at_rest(servo_run):
    _, stress = servo_run
    # measured 2026-12-03: 1.08 % apart, P 0.60 % apart (the walls'
    # estimate stays 1 % off: docs/loading_stress.md)
    assert stress["difference"][-1] < 0.02
    assert stress["contact_P"][-1] == pytest.approx(stress["wall_P"][-1],
                                                    rel=0.02)
    # with wall friction the mean stress is below the imposed pressure
    assert 0.5 * TARGET < stress["wall_P"][-1] <= TARGET * 1.01


def test_the_energy_balance_counts_the_imposed_work(servo_run):
    """At every output row (measured 2026-12-03: at most 3.4e-5 of the work
    done so far, the last rows; the first row has no work yet and a zero
    residual, bounded against the final work)."""
    steps, _ = servo_run
    work = steps["wall_work"]
    residual = np.abs(steps["energy_residual"])
    assert work[-1] > 0 and work[0] == 0
    assert np.all(residual < 3.5e-4 * work[-1]), residual.max() / work[-1]
    done = work > 0
    assert done.sum() == len(work) - 1
    assert np.all(residual[done] < 3.5e-4 * work[done]), \
        (residual[done] / work[done]).max()
