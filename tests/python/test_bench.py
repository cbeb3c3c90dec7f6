"""The invariance comparison used by ./softpack bench --invariance."""

import numpy as np
import pytest

from softpack.bench.paper import compare_series


def _series(scale_phi=1.0, shift_z=0.0):
    eps = np.linspace(0.0, 0.05, 11)
    phi = 0.75 * np.exp(eps) * scale_phi
    return {"eps": list(eps), "phi": list(phi),
            "E_over_WHLmu": list((phi - 0.74) ** 2),
            "z": list(3 + 10 * (phi - 0.75) + shift_z)}


def test_identical_runs_differ_by_nothing():
    d = compare_series(_series(), _series())
    assert d["phi_max_relative_difference"] == pytest.approx(0, abs=1e-15)
    assert d["energy_max_relative_difference"] == pytest.approx(0, abs=1e-12)
    assert d["z_max_difference"] == pytest.approx(0, abs=1e-12)
    assert d["eps_range"] == pytest.approx([0.0, 0.05])


def test_known_differences_are_measured():
    d = compare_series(_series(), _series(scale_phi=1.001, shift_z=0.03))
    assert d["phi_max_relative_difference"] == pytest.approx(1e-3, rel=1e-6)
    assert d["z_max_difference"] == pytest.approx(0.03, abs=2e-3)


def test_bench_configs_are_validated_with_their_overrides(registry):
    """The bench builds its configs by overrides before validation: the
    scaled box keeps the initial packing fraction and the strain rate, a
    fixed step count is [stop] steps."""
    from softpack.bench import common as bench
    from softpack.scene.config import initial_packing_fraction, load_config

    base = load_config(bench.PAPER_TOML)
    config = bench.scaled_config(4, {**bench.FAST, "stop.steps": 7})
    assert [s["count"] for s in config["species"]] == [280, 120]
    assert initial_packing_fraction(config) == pytest.approx(
        initial_packing_fraction(base), rel=1e-12)
    rate = lambda c: -c["walls"]["right"]["velocity"][0] / c["box"]["length"]
    assert rate(config) == pytest.approx(rate(base), rel=1e-12)
    assert config["stop"]["steps"] == 7 and config["output"]["fields"] is False
    # max_time follows the scaled box: the piston crosses half of it
    assert config["stop"]["max_time"] == pytest.approx(base["stop"]["max_time"])
    quarter = bench.scaled_config(0.25, {})
    assert [s["count"] for s in quarter["species"]] == [18, 8]


CONTACTS = "candidate,node,antagonist,wall,fn\n"


def _raw_run(root, name, phi_shift=0.0, contact_text="1,2,3,-1,5.0\n"):
    raw = root / name / "raw"
    (raw / "contacts").mkdir(parents=True)
    (raw / "steps.csv").write_text(
        "step,phi,strain_energy\n"
        f"0,{0.80 + phi_shift!r},1.0\n12,{0.81 + phi_shift!r},2.0\n")
    for step in (0, 12):
        (raw / "contacts" / f"step_{step:08d}.csv").write_text(
            CONTACTS + (contact_text if step == 12 else "1,2,3,-1,5.0\n"))
    return root / name


def test_a_run_on_other_ranks_is_compared_step_by_step(tmp_path):
    """bench --mpi --mpi-to-phi: Phi, E and the contacts of every output
    step against the 1-rank run; a file with other contacts is named, and
    the normal forces of the same contacts are compared."""
    from softpack.bench.mpi import same_run

    serial = _raw_run(tmp_path, "one")
    same = same_run(serial, _raw_run(tmp_path, "two"))
    assert same["phi_max_abs_diff"] == 0.0
    assert same["strain_energy_max_rel_diff"] == 0.0
    assert same["contact_files"] == 2
    assert same["contacts_in_one_run_only"] == {}
    assert same["fn_max_rel_diff"] == 0.0
    other = same_run(serial, _raw_run(tmp_path, "four", phi_shift=1e-6,
                                      contact_text="1,7,3,-1,5.0\n"))
    assert other["phi_max_abs_diff"] == pytest.approx(1e-6, rel=1e-6)
    assert other["contacts_in_one_run_only"] == {
        "step_00000012.csv": [(1, 2, 3, -1), (1, 7, 3, -1)]}
    forces = same_run(serial, _raw_run(tmp_path, "five",
                                       contact_text="1,2,3,-1,5.5\n"))
    assert forces["contacts_in_one_run_only"] == {}
    assert forces["fn_max_rel_diff"] == pytest.approx(0.1)


def test_times_are_normalised_to_the_reference_yardstick():
    """Issue 41 item 2: a time measured while the yardstick ran at half the
    reference's speed is half as long at the reference's; the tables say
    both."""
    from softpack.bench import paper
    from softpack.bench.common import REFERENCE_YARDSTICK, normalised

    assert normalised(600.0, REFERENCE_YARDSTICK / 2) == 300.0
    assert normalised(600.0, REFERENCE_YARDSTICK) == 600.0
    assert normalised(600.0, None) != normalised(600.0, None)  # NaN
    report = {"nlgs": {"sweeps_per_second": 2 * REFERENCE_YARDSTICK},
              "detection": [], "paper": [],
              "full": {"minutes": 10.0, "seconds": 600.0, "steps": 7524}}
    text = paper.table(report)
    assert "85600 sweeps/s" in text
    assert "full paper case (defaults): 10.0 min (1200 s at 42,800" in text
