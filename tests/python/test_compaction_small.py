"""End to end on the CI-sized case (examples/small.toml, 14 disks, 3 mm
elements): the real driver compresses the packing to Phi = 0.80.

Checks the physics the paper case relies on: Phi grows monotonically with
eps, the energy balance closes, contacts do not penetrate, and the initial
packing has no overlap.
"""

import csv
import os
from pathlib import Path

import numpy as np
import pytest

from softpack import config as cfg
from softpack.packing import Packing
from softpack.run import driver_executable, run

ROOT = Path(os.environ.get("SOFTPACK_ROOT", Path(__file__).resolve().parents[2]))


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    if not driver_executable().exists():
        pytest.skip("softpack-simulate is not built (run ./softpack test)")
    out = tmp_path_factory.mktemp("small") / "run"
    config = cfg.load_config(ROOT / "examples" / "small.toml")
    assert run(config, out) == 0
    with open(out / "series.csv") as f:
        rows = list(csv.DictReader(f))
    series = {k: np.array([float(r[k]) if r[k] not in ("", "nan") else np.nan
                           for r in rows]) for k in rows[0]}
    return config, out, series


def test_reaches_the_target_packing_fraction(small_run):
    config, out, s = small_run
    assert s["phi"][-1] >= config["loading"]["target_packing_fraction"]
    assert (out / "raw" / "done.json").exists()


def test_packing_fraction_rises_monotonically_with_strain(small_run):
    _, _, s = small_run
    assert np.all(np.diff(s["eps"]) > 0)
    assert np.all(np.diff(s["phi"]) > 0)


def test_energy_balance_closes_within_one_percent(small_run):
    _, _, s = small_run
    work = s["wall_work"]
    assert work[-1] > 0
    late = work > 0.05 * work[-1]
    assert np.all(np.abs(s["energy_residual"][late]) < 0.01 * work[late])
    # the piston's work is stored or dissipated, not lost
    assert s["strain_energy"][-1] > 0.3 * work[-1]


def test_contacts_do_not_penetrate(small_run):
    config, _, s = small_run
    # predicted gaps at the end of each step, against the element size
    assert np.nanmax(s["max_penetration"]) < 1e-4 * config["mesh"]["element_size"]


def test_initial_packing_has_no_overlap(small_run):
    config, out, _ = small_run
    packing = Packing.from_csv(next((out / "mesh").glob("*.packing.csv")))
    assert packing.min_particle_gap() > 0
    assert packing.min_wall_gap() > 0
