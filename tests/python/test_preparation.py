"""A preparation protocol in a periodic cell (docs/preparation.md; issue 38
item 4): examples/prepare_cell.toml on 14 disks and a 3 mm mesh, its
frictionless stages shortened to 0.05 s. The frictionless compaction and
release dissipate nothing by friction; the release lets the packing expand;
with the friction switched on the assembly comes to rest (the stage ends by
its equilibrium criterion, under the cell's mass damping) where the
contacts' and the bodies' own mean stress hold the imposed 2 kPa.
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from driver_required import require_driver
from softpack.contract.tables import read_table
from softpack.scene.config import validate
from softpack.simulation.run import run

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" \
    / "prepare_cell.toml"

pytestmark = pytest.mark.usefixtures("registry")


def small_example():
    """The example on 14 disks in a 100 x 85 mm cell, 3 mm mesh."""
    data = tomllib.loads(EXAMPLE.read_text())
    data["species"][0]["count"] = 10
    data["species"][1]["count"] = 4
    data["cell"]["a1"] = [0.1, 0.0]
    data["cell"]["a2"] = [0.0, 0.085]
    data["mesh"]["element_size"] = 3e-3
    data["contact"]["alert_distance"] = 1e-3
    data["contact"]["max_penetration"] = 1.5e-3
    for stage in data["stages"][:2]:
        stage["stop"]["max_time"] = 0.05
    data["output"]["every_steps"] = 10
    return data


@pytest.fixture(scope="module")
def prepared(tmp_path_factory):
    require_driver()
    out = tmp_path_factory.mktemp("preparation") / "run"
    assert run(validate(small_example(), "prepared"), out) == 0
    return out


def test_the_example_is_three_stages_under_the_mean_stress():
    data = validate(tomllib.loads(EXAMPLE.read_text()), "example")
    names = [s["name"] for s in data["stages"]]
    assert names == ["compact", "release", "friction"]
    assert [s["contact"]["friction"] for s in data["stages"]] == [0.0, 0.0,
                                                                  0.3]
    assert [s["cell"]["stress_mean"] for s in data["stages"]] == [
        10e3, 2e3, 2e3]


def test_friction_acts_only_once_switched_on(prepared):
    steps = read_table(prepared / "raw" / "steps.csv")
    stage = np.asarray(steps["stage"])
    friction = np.asarray(steps["friction"])
    assert set(stage) == {0, 1, 2}
    assert np.all(friction[stage < 2] == 0.0)
    assert friction[-1] > 0.0


def test_the_release_expands_the_packing(prepared):
    steps = read_table(prepared / "raw" / "steps.csv")
    stage = np.asarray(steps["stage"])
    phi = np.asarray(steps["phi"])
    # measured 0.925 after the compaction, 0.842 after the release
    # (2026-12-04)
    assert phi[stage == 0][-1] > phi[stage == 1][-1] + 0.03


def test_the_friction_stage_ends_at_rest_under_the_imposed_stress(prepared):
    steps = read_table(prepared / "raw" / "steps.csv")
    stress = read_table(prepared / "stress.csv")
    # ended by its equilibrium criterion, before its max_time (0.4 s)
    assert steps["time"][-1] < 0.05 + 0.05 + 0.4 - 1e-6
    # measured 1,999.9 Pa (contacts) and 1,999.8 Pa (the bodies' own
    # stress) at rest (2026-12-04)
    assert stress["contact_P"][-1] == pytest.approx(2000.0, rel=5e-3)
    assert stress["fe_P"][-1] == pytest.approx(2000.0, rel=5e-3)
